#include "io/run_output.hpp"

#include "core/errors.hpp"
#include "core/options.hpp"
#include "io/io_options.hpp"
#include "io/files.hpp"

#include <algorithm>

namespace aries::io {

const std::vector<OutputField> &outputFields() {
  using S = FieldSource;
  static const std::vector<OutputField> fields = {
      {"alpha", S::CellQuantities, 1, "the singularity measure alpha (rest: 64 for tets, 2 for triangles; 0: inverted "
                                      "or degenerate)"},
      {"energy_density", S::CellQuantities, 1, "Psi(F), energy per unit rest measure"},
      {"fiber", S::Fibers, 3, "rest fiber direction a (0 without fibers)"},
      {"J", S::StressMeasures, 1, "det F (signed; < 0 = inverted); for cloth the area ratio sqrt(det F^T F)"},
      {"von_mises", S::StressMeasures, 1, "sqrt(3/2 s:s) of the Cauchy stress's deviator s"},
      {"cauchy_stress", S::StressMeasures, 9, "sigma = P F^T / J (NaN where J = 0)"},
      {"pk1_stress", S::StressMeasures, 9, "first Piola-Kirchhoff stress P = dPsi/dF (rest frame columns)"},
      {"green_strain", S::StressMeasures, 9, "Green-Lagrange strain (F^T F - I) / 2 (triangles: the in-plane part, in 3D)"},
      {"principal_stretches", S::StressMeasures, 3,
       "singular values of F, largest first; the smallest is negative in an inverted tet (signed singular values); "
       "triangles write 1 as the third"},
      {"deformation_gradient", S::StressMeasures, 9, "F from the rest shape to the current shape (rows beyond the space "
                                                     "dimension 0)"},
      {"region", S::Regions, 1, "0 = the global material, k = the k-th -regions entry"},
      {"velocity", S::Velocity, 3, "backward Euler velocity of the free components (0 in held ones)"},
      {"reaction", S::Reactions, 3, "in the held components of Dirichlet vertices dE/dx, the force the support "
                                    "exerts (its sum over a set = the -reactions row); 0 elsewhere"},
      {"marker", S::Markers, 1, "k for a vertex of the k-th Dirichlet set (-bc_clamp ids in order, then -bc_box "
                                "boxes), 0 if free"},
  };
  return fields;
}


namespace {

std::string fieldNames() {
  std::string names;
  for (const auto &f : outputFields()) names += (names.empty() ? "" : "|") + std::string(f.name);
  return names;
}

std::vector<std::string> splitCommas(const std::string &s) {
  std::vector<std::string> out;
  size_t start = 0;
  while (start <= s.size()) {
    const size_t comma = s.find(',', start);
    out.push_back(s.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

}  // namespace

PetscErrorCode readOutputOptions(bool dynamic, OutputOptions *o) {
  PetscBool set = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCall(core::get(opt::output, &o->output, &set));
  if (set) {
    PetscCall(core::get(opt::outputEvery, &o->outputEvery));
    std::string list;
    PetscCall(core::get(opt::outputFields, &list));
    o->fields.clear();
    for (const std::string &name : list == "all" ? std::vector<std::string>{} : splitCommas(list)) {
      const OutputField *f = nullptr;
      for (const auto &g : outputFields())
        if (name == g.name) f = &g;
      if (!f)
        SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -output_fields: '%s' is not a field (%s, or all)",
                name.c_str(), fieldNames().c_str());
      if (f->source == FieldSource::Velocity && !dynamic)
        SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
                "option -output_fields: '%s' needs -integrator beuler (a static run has no velocities)", name.c_str());
      if (std::find(o->fields.begin(), o->fields.end(), name) != o->fields.end())
        SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -output_fields: '%s' is listed twice", name.c_str());
      o->fields.push_back(name);
    }
    if (list == "all")
      for (const auto &g : outputFields())
        if (dynamic || g.source != FieldSource::Velocity) o->fields.push_back(g.name);
  }
  PetscCall(core::get(opt::stats, &o->stats));
  PetscCall(core::get(opt::reactions, &o->reactions));
  PetscCall(core::get(opt::newtonHistory, &o->newtonHistory));
  PetscFunctionReturn(0);
}

RunOutput::~RunOutput() {
  if (reactions_) std::fclose(reactions_);
  if (history_) std::fclose(history_);
}

PetscErrorCode RunOutput::setup(const OutputOptions &opts, const CheckpointOptions &checkpoint,
                                const fem::Discretization &disc, PetscInt resumeAfterStep) {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  opts_ = opts;
  checkpoint_ = checkpoint;
  PetscCall(PetscObjectGetComm((PetscObject)disc.dm(), &comm_));
  PetscCallMPI(MPI_Comm_rank(comm_, &rank));
  if (!opts.stats.empty()) PetscCall(stats_.open(comm_, opts.stats, resumeAfterStep));
  if (!opts.reactions.empty()) {
    if (rank == 0) {
      reactions_ = makeParentDirectory(opts.reactions) ? std::fopen(opts.reactions.c_str(), "w") : nullptr;
      if (reactions_) std::fprintf(reactions_, "step,time,set,fx,fy,fz\n");
    }
    PetscCall(core::collectiveCheck(comm_, rank == 0 && !reactions_,
                                   "cannot open reactions file '" + opts.reactions + "' for writing (-reactions)"));
  }
  if (!opts.newtonHistory.empty()) {
    if (rank == 0) {
      history_ = makeParentDirectory(opts.newtonHistory) ? std::fopen(opts.newtonHistory.c_str(), "w") : nullptr;
      if (history_)
        std::fprintf(history_, "step,iteration,energy,residual,step_inf,lambda,ksp_its,filter,subspace,rotation,level,"
                               "load,lifted,extrapolated,solve,pc_built\n");
    }
    PetscCall(core::collectiveCheck(comm_, rank == 0 && !history_,
                                   "cannot open Newton history file '" + opts.newtonHistory +
                                       "' for writing (-newton_history)"));
  }
  if (!opts.output.empty() || checkpoint.every > 0) {  // the natural-order blocks each rank writes
    std::vector<PetscInt> ids;
    disc.diagnostics().ownedVertexIds(&ids);
    PetscCall(vertexBlocks_.setup(comm_, disc.mesh().numVerticesGlobal, ids));
    disc.diagnostics().ownedCellIds(&ids);
    PetscCall(cellBlocks_.setup(comm_, disc.mesh().numCellsGlobal, ids));
  }
  if (!opts.output.empty()) {
    std::vector<PetscInt> cells;
    std::vector<double> rest;
    disc.diagnostics().ownedTopology(&cells);
    disc.diagnostics().ownedRestPositions(&rest);
    PetscCall(writer_.open(comm_, opts.output, vertexBlocks_, cellBlocks_, cells, disc.verticesPerCell(),
                           disc.outputTopology(), rest, resumeAfterStep));
  }
  PetscCall(PetscLogStageGetId("output", &outputStage_));
  if (outputStage_ < 0) PetscCall(PetscLogStageRegister("output", &outputStage_));
  PetscFunctionReturn(0);
}

PetscErrorCode RunOutput::writeState(const solver::Simulation &sim, PetscInt step, double time) {
  PetscFunctionBeginUser;
  if (!writer_.isOpen()) PetscFunctionReturn(0);
  const fem::Discretization &disc = sim.discretization();
  PetscCall(PetscLogStagePush(outputStage_));
  Vec xLocal;
  PetscCall(DMGetLocalVector(disc.dm(), &xLocal));
  PetscCall(sim.localState(xLocal));
  std::vector<double> positions;
  PetscCall(disc.diagnostics().ownedVertexValues(xLocal, &positions));
  std::vector<const OutputField *> selected;
  for (const auto &f : outputFields())
    if (std::find(opts_.fields.begin(), opts_.fields.end(), f.name) != opts_.fields.end()) selected.push_back(&f);
  const auto needs = [&](FieldSource src) {
    return std::any_of(selected.begin(), selected.end(), [&](const OutputField *f) { return f->source == src; });
  };
  fem::CellQuantities q;
  std::vector<kernels::StressMeasures> sm;
  std::vector<double> fibers, regions;
  if (needs(FieldSource::CellQuantities)) PetscCall(disc.diagnostics().cellQuantities(xLocal, &q));
  if (needs(FieldSource::StressMeasures)) PetscCall(disc.diagnostics().cellStressMeasures(xLocal, &sm));
  if (needs(FieldSource::Fibers)) PetscCall(disc.diagnostics().cellFibers(&fibers));
  if (needs(FieldSource::Regions)) disc.diagnostics().cellRegions(&regions);
  PetscCall(writer_.beginStep(step, time, positions));
  positions = std::vector<double>();
  for (const OutputField *f : selected) {  // one field at a time: computed, written, released
    const std::string name = f->name;
    CellField out{name, f->components, {}};
    std::vector<double> local;  // per local cell, f->components each
    switch (f->source) {
      case FieldSource::CellQuantities: local = name == "alpha" ? q.alpha : q.energyDensity; break;
      case FieldSource::Fibers: local = fibers; break;
      case FieldSource::Regions: local = regions; break;
      case FieldSource::StressMeasures: {
        // what of kernels::StressMeasures this field writes, chosen once
        using M = kernels::StressMeasures;
        const Eigen::Matrix3d M::*tensor = name == "cauchy_stress" ? &M::cauchy
                                           : name == "pk1_stress"  ? &M::pk1
                                           : name == "green_strain" ? &M::greenLagrange
                                                                    : &M::deformationGradient;
        const bool isJ = name == "J", isVonMises = name == "von_mises";
        local.reserve(sm.size() * f->components);
        for (const M &m : sm) {
          if (isJ) local.push_back(m.J);
          else if (isVonMises) local.push_back(m.vonMises);
          else if (f->components == 3)
            local.insert(local.end(), m.principalStretches.begin(), m.principalStretches.end());
          else
            for (int i = 0; i < 3; ++i)
              for (int j = 0; j < 3; ++j) local.push_back((m.*tensor)(i, j));  // row-major, as XDMF's Tensor
        }
        break;
      }
      case FieldSource::Velocity: {
        Vec vLocal;
        PetscCall(DMGetLocalVector(disc.dm(), &vLocal));
        PetscCall(sim.localVelocity(vLocal));
        PetscCall(disc.diagnostics().ownedVertexValues(vLocal, &out.values));
        PetscCall(DMRestoreLocalVector(disc.dm(), &vLocal));
        break;
      }
      case FieldSource::Reactions: PetscCall(disc.diagnostics().ownedVertexReactions(xLocal, &out.values)); break;
      case FieldSource::Markers: disc.diagnostics().ownedVertexMarkers(&out.values); break;
    }
    if (f->perCell()) disc.diagnostics().ownedCellValues(local, f->components, &out.values);
    PetscCall(writer_.writeField(out, f->perCell()));
  }
  PetscCall(DMRestoreLocalVector(disc.dm(), &xLocal));
  PetscCall(writer_.endStep());
  PetscCall(PetscLogStagePop());
  PetscFunctionReturn(0);
}

PetscErrorCode RunOutput::initial(const solver::Simulation &sim) {
  PetscFunctionBeginUser;
  const double t0 = MPI_Wtime();
  PetscCall(writeState(sim, 0, 0.0));
  seconds_ += MPI_Wtime() - t0;
  PetscFunctionReturn(0);
}

namespace {

// "42.0s", "3m07s", "2h05m": a duration for the progress line.
std::string clockTime(double seconds) {
  char buf[32];
  if (seconds < 60.0) std::snprintf(buf, sizeof buf, "%.1fs", seconds);
  else if (seconds < 3600.0) std::snprintf(buf, sizeof buf, "%dm%02ds", (int)(seconds / 60), (int)seconds % 60);
  else std::snprintf(buf, sizeof buf, "%dh%02dm", (int)(seconds / 3600), ((int)seconds % 3600) / 60);
  return buf;
}

}  // namespace

// Everything after a step (statistics, reactions, history, the step line, files) counts as output time.
PetscErrorCode RunOutput::afterStep(const solver::Simulation &sim, const solver::StepReport &rep) {
  PetscFunctionBeginUser;
  const double t0 = MPI_Wtime();
  PetscCall(record(sim, rep));
  seconds_ += MPI_Wtime() - t0;
  PetscFunctionReturn(0);
}

PetscErrorCode RunOutput::record(const solver::Simulation &sim, const solver::StepReport &rep) {
  PetscFunctionBeginUser;
  const fem::Discretization &disc = sim.discretization();
  Vec xLocal;
  PetscCall(DMGetLocalVector(disc.dm(), &xLocal));
  PetscCall(sim.localState(xLocal));
  StepStats st;
  st.step = rep.step;
  st.time = rep.time;
  st.newtonIterations = rep.newton.newtonIterations;
  st.linearIterations = rep.newton.linearIterations;
  st.wallSeconds = rep.wallSeconds;
  st.reason = rep.reason;
  st.linearSolves = rep.newton.linearSolves;
  st.linearAtLimit = rep.newton.linearAtLimit;
  st.localIterations = rep.newton.localIterations;
  st.residual = rep.newton.residualNorm;
  st.barrierFallback = rep.newton.barrierFallbackCells;
  st.barrierCells = rep.newton.barrierActiveCells;
  st.coarseNewton = rep.coarse.newtonIterations;
  st.coarseLinear = rep.coarse.linearIterations;
  st.coarseStart = rep.coarseStart;
  PetscCall(disc.diagnostics().elasticEnergy(xLocal, &st.energy));
  PetscCall(disc.diagnostics().minAlpha(xLocal, &st.minAlpha));
  PetscCall(disc.diagnostics().maxDisplacement(xLocal, &st.maxDisplacement));
  PetscCall(stats_.append(st));
  if (!opts_.reactions.empty())
    for (size_t set = 0; set < disc.boundary().sets.size(); ++set) {
      Eigen::Vector3d f;
      PetscCall(disc.diagnostics().reactionForce(xLocal, set, &f));
      if (reactions_) {
        std::fprintf(reactions_, "%d,%.10g,%s,%.17g,%.17g,%.17g\n", (int)rep.step, rep.time,
                     disc.boundary().sets[set].id.c_str(), f[0], f[1], f[2]);
        std::fflush(reactions_);
      }
    }
  PetscCall(DMRestoreLocalVector(disc.dm(), &xLocal));
  if (history_) {
    // The coarse levels' rows first (their solves come first), each marked with its level; solve counts the step's
    // Newton solves (a failed unfiltered first system repeats iteration 0 within one solve).
    int solve = 0;
    for (const auto *rows : {&rep.coarse.history, &rep.newton.history})
      for (const auto &h : *rows) {
        if (h.firstOfSolve || solve == 0) ++solve;
        std::fprintf(history_, "%d,%d,%.17g,%.6e,%.6e,%.6g,%d,%s,%d,%g,%d,%.17g,%d,%g,%d,%d\n", (int)rep.step,
                     (int)h.iteration, h.energy, h.residual, h.stepInf, h.lambda, (int)h.linearIterations,
                     h.filter == 'a' ? "abs" : h.filter == 'n' ? "none" : "clamp", h.accelerated ? 1 : 0, h.rotation,
                     h.level, h.load, h.lifted ? 1 : 0, h.extrapolated, solve, h.preconditionerBuilt ? 1 : 0);
      }
    std::fflush(history_);
  }
  const std::string halved =
      rep.newton.safeguardHalvings ? " (safeguard halved the step " + std::to_string(rep.newton.safeguardHalvings) + "x)" : "";
  const std::string atLimit =
      rep.newton.linearAtLimit ? " (" + std::to_string(rep.newton.linearAtLimit) + " at -ksp_max_it)" : "";
  const std::string local =
      rep.newton.localIterations ? "  local " + std::to_string(rep.newton.localIterations) : "";
  const std::string coarse = rep.coarseStart < 0 ? std::string()
                             : "  coarse newton " + std::to_string(rep.coarse.newtonIterations) + " cg " +
                                   std::to_string(rep.coarse.linearIterations) +
                                   (rep.coarseStart ? " (start taken)" : " (start not taken)");
  // Progress: wall time since this run's first step and the remaining steps at this run's average pace.
  if (runStart_ < 0.0) {
    runStart_ = MPI_Wtime() - rep.wallSeconds;
    firstStep_ = rep.step;
  }
  const double elapsed = MPI_Wtime() - runStart_;
  const double eta = elapsed / static_cast<double>(rep.step - firstStep_ + 1) * static_cast<double>(rep.steps - rep.step);
  PetscCall(PetscPrintf(comm_,
                        "step %d/%d  t=%g  newton %d%s  solves %d  cg %d%s%s  min_alpha %.3e  |r| %.2e  %.3f s  %s%s  "
                        "[elapsed %s, eta %s]\n",
                        (int)rep.step, (int)rep.steps, rep.time, (int)rep.newton.newtonIterations, local.c_str(),
                        (int)rep.newton.linearSolves, (int)rep.newton.linearIterations, atLimit.c_str(), coarse.c_str(),
                        st.minAlpha,
                        rep.newton.residualNorm, rep.wallSeconds, rep.reason.c_str(), halved.c_str(),
                        clockTime(elapsed).c_str(), clockTime(eta).c_str()));
  if (!rep.ok && rep.newton.mollifierBandCells > 0)  // why such solves stall: bench/results/degenerate_starts_band.md
    PetscCall(PetscPrintf(comm_,
                          "aries: step %d did not converge with %d cell%s held at the singularity mollifier's band "
                          "at its last iterate (the band's coordinate, alpha or its scale-free form "
                          "(-mollifier_measure), in [eps, %g x 3 eps]; the band of Eq. 33 is [eps, 3 eps], "
                          "-mollifier_eps), where the I4/I6 terms' forces peak\n",
                          (int)rep.step, (int)rep.newton.mollifierBandCells,
                          rep.newton.mollifierBandCells == 1 ? "" : "s", fem::Discretization::kMollifierBandEdge));
  if (rep.step % opts_.outputEvery == 0 || rep.stopping) PetscCall(writeState(sim, rep.step, rep.time));
  if (checkpoint_.every > 0 && (rep.step % checkpoint_.every == 0 || rep.stopping)) {
    PetscCall(PetscLogStagePush(outputStage_));
    PetscCall(writeCheckpoint(sim, vertexBlocks_, checkpoint_.path));
    PetscCall(PetscLogStagePop());
  }
  PetscFunctionReturn(0);
}

}  // namespace aries::io
