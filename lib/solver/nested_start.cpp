// Nested iteration (grid sequencing) on meshes that need not be nested (-coarse_mesh, -coarse_steps): a step is first
// solved on a coarse mesh of the same body, and its solution, interpolated (mesh/mesh_transfer.hpp), starts the solve
// on the finer mesh.
//
// Why: from a degenerate start (inside out, scrambled, collapsed) Newton's work is in fronts and unwinding that move
// about one cell layer per update, so the number of updates grows with the number of cell layers, i.e. with the
// resolution (the inside-out bunny's first step: 106 updates at 35k tets, 237 at 639k). On a coarse mesh the same
// motion crosses fewer layers, and the fine solve that starts from its interpolated solution only corrects what the
// coarse mesh could not represent. Each coarse level is a Simulation of its own (its state, velocities, Newton solver,
// and its own coarser level), so any number of levels nest.
//
// Each coarse level reads the run's options on its own mesh; per-cell files are read at the fine cell that contains
// each coarse cell's centroid. The coarse level solves the same step:
//  * a synthetic start's first step (scramble, invert, collapse; not a restart): from the coarse mesh's own synthetic
//    start (the same rule; for scramble its own random positions, since a fine scramble has no coarse counterpart),
//    with its own detached start for static runs; the fine solve starts from the rest positions plus the interpolated
//    coarse displacement and skips its own detached start;
//  * any other step: from the finer level's accepted state and velocities interpolated to the coarse vertices; the
//    fine solve starts from its own start plus the interpolated coarse correction (the coarse solution minus the coarse
//    start), which keeps the finer level's detail.
// The start is taken only where it lowers the fine total potential and keeps every guarded alpha acceptable (the
// predictor's rule); otherwise, or when the coarse solve fails, the fine solve starts as it would without the levels.
// The coarse levels' Newton updates and linear iterations are counted apart from the fine ones (StepReport::coarse;
// stats columns coarse_newton_its and coarse_ksp_its, -newton_history column level), and the step's wall time includes
// them and the interpolations.
#include "solver/coarse_level.hpp"

#include "fem/discretization_options.hpp"

#include <petscsys.h>

namespace aries::solver {

namespace {

// Per local vertex (3 each): the displacement from rest at a global state (Dirichlet values filled), or the values
// of a velocity-like global vector (0 at Dirichlet dofs).
PetscErrorCode vertexField(const fem::Discretization &disc, Vec global, bool displacement, std::vector<double> *out) {
  Vec local;
  PetscFunctionBeginUser;
  PetscCall(DMGetLocalVector(disc.dm(), &local));
  PetscCall(VecZeroEntries(local));
  PetscCall(DMGlobalToLocal(disc.dm(), global, INSERT_VALUES, local));
  if (displacement) PetscCall(disc.fillBoundary(local));
  PetscCall(disc.kinematics().vertexPositions(local, out));
  PetscCall(DMRestoreLocalVector(disc.dm(), &local));
  if (displacement) {
    std::vector<Eigen::Vector3d> rest;
    PetscCall(fem::vertexRestPositions(disc.mesh(), &rest));
    for (size_t v = 0; v < rest.size(); ++v)
      for (int i = 0; i < 3; ++i) (*out)[3 * v + i] -= rest[v][i];
  }
  PetscFunctionReturn(0);
}

// global += values per local vertex, at the owned free dofs.
PetscErrorCode addVertexField(const fem::Discretization &disc, const std::vector<double> &values, Vec global) {
  PetscInt lo;
  PetscScalar *x;
  PetscFunctionBeginUser;
  PetscCall(VecGetOwnershipRange(global, &lo, nullptr));
  PetscCall(VecGetArray(global, &x));
  disc.kinematics().forEachOwnedFreeVertex([&](PetscInt local, PetscInt, const PetscInt *rows, const Eigen::Vector3d &) {
    for (int i = 0; i < 3; ++i)
      if (rows[i] >= 0) x[rows[i] - lo] += values[3 * static_cast<size_t>(local) + i];
  });
  PetscCall(VecRestoreArray(global, &x));
  PetscFunctionReturn(0);
}

// Per-cell input files (-fiber_file, -target_file) give values for the cells of the run's mesh: each coarse cell reads
// them at the cell of the finer mesh that contains its rest centroid (that cell's own file cell on a deeper level).
PetscErrorCode readFilesAtFineCells(const fem::Mesh &fine, const std::string &what, fem::Mesh *coarse) {
  PetscFunctionBeginUser;
  std::vector<Eigen::Vector3d> rest, centroids;
  PetscCall(fem::vertexRestPositions(*coarse, &rest));
  std::vector<PetscInt> verts;
  for (PetscInt c = coarse->cStart; c < coarse->cEnd; ++c) {
    PetscCall(fem::closureVertices(*coarse, c, &verts));
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (PetscInt v : verts) sum += rest[v];
    centroids.push_back(sum / static_cast<double>(verts.size()));
  }
  PetscCall(fem::valuesOfCellsAt(fine, fine.fileCells(), *coarse, centroids, what + ", its cell centroids",
                                 &coarse->fileCell));
  coarse->fileCellsGlobal = fine.fileCellCount();
  coarse->readsOtherMeshFiles = true;
  PetscFunctionReturn(0);
}

}  // namespace

PetscErrorCode Simulation::setupCoarseLevels() {
  MPI_Comm comm;
  PetscFunctionBeginUser;
  if (opts_.coarseMeshes.empty()) PetscFunctionReturn(0);
  PetscCall(PetscObjectGetComm((PetscObject)disc_->dm(), &comm));
  const std::string file = opts_.coarseMeshes.front();
  const fem::Mesh &fine = disc_->mesh();
  if (fine.shape != energies::ElementShape::Tet || fine.hexahedra || fine.quadratic)
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
            "option -coarse_mesh: nested iteration needs linear tetrahedra, and '%s' is a %s mesh",
            fine.filename.c_str(),
            fine.hexahedra ? "hexahedral" : fine.quadratic ? "quadratic (-element p2)" : "surface");
  coarse_ = std::make_unique<CoarseLevel>();
  CoarseLevel &c = *coarse_;
  PetscCall(fem::loadMesh(comm, &c.mesh, file, "-coarse_mesh"));
  if (c.mesh.hexahedra)
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
            "option -coarse_mesh: nested iteration needs tetrahedral meshes, and '%s' is a hexahedral mesh",
            file.c_str());
  if (c.mesh.numCellsGlobal >= fine.numCellsGlobal)
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
            "option -coarse_mesh: '%s' has %d cells, not fewer than the %d of '%s' (coarse meshes come coarsest last)",
            file.c_str(), (int)c.mesh.numCellsGlobal, (int)fine.numCellsGlobal, fine.filename.c_str());
  const std::string what = "option -coarse_mesh ('" + file + "' for '" + fine.filename + "')";
  PetscCall(readFilesAtFineCells(fine, what, &c.mesh));
  fem::FemOptions femOpts;
  PetscCall(fem::readFemOptions(c.mesh, syntheticStart(opts_.initial), &femOpts));
  const bool dynamic = opts_.integrator == Integrator::BackwardEuler;
  PetscCall(fem::Discretization::create(c.mesh, femOpts, dynamic ? opts_.dt : 0.0, &c.disc));
  SimulationOptions coarseOpts = opts_;
  coarseOpts.coarseMeshes.erase(coarseOpts.coarseMeshes.begin());
  coarseOpts.onFailure = FailurePolicy::Stop;  // a failed coarse solve hands its start back and is not used
  c.sim.level_ = level_ + 1;
  PetscCall(c.sim.setup(*c.disc, coarseOpts));
  PetscCall(c.toFine.setup(c.mesh, fine, what));
  PetscCall(c.fromFine.setup(fine, c.mesh, what));
  PetscCall(PetscPrintf(comm,
                        "aries: nested iteration level %d: %s, %d cells, %d vertices; its vertices outside the finer "
                        "mesh by at most %.3g, the finer mesh's outside it by at most %.3g\n",
                        level_ + 1, file.c_str(), (int)c.mesh.numCellsGlobal, (int)c.mesh.numVerticesGlobal,
                        c.fromFine.largestOutsideDistance(), c.toFine.largestOutsideDistance()));
  PetscFunctionReturn(0);
}

bool Simulation::nestedStep(PetscInt step) const {
  return coarse_ && (opts_.coarseSteps < 0 || step <= opts_.coarseSteps);
}

// The coarse level's state (positions, or velocities) from this level's global vector `fine`.
PetscErrorCode Simulation::restrictTo(CoarseLevel &coarse, Vec fine, bool positions, Vec xCoarse) {
  std::vector<double> here, there;
  PetscFunctionBeginUser;
  PetscCall(vertexField(*disc_, fine, positions, &here));
  PetscCall(coarse.fromFine.interpolate(here, &there));
  if (positions) PetscCall(coarse.disc->restPositions(xCoarse));
  else PetscCall(VecZeroEntries(xCoarse));
  PetscCall(addVertexField(*coarse.disc, there, xCoarse));
  PetscFunctionReturn(0);
}

// Called by advance() once the trial step is set (xPrev_, vPrev_: the accepted state; x_: the start Newton would take).
PetscErrorCode Simulation::startFromCoarse(double dt, double loadTarget, bool *used) {
  PetscFunctionBeginUser;
  *used = false;
  CoarseLevel &c = *coarse_;
  Simulation &cs = c.sim;
  const bool dynamic = opts_.integrator == Integrator::BackwardEuler;
  const bool fromSynthetic = currentStep_ == 1 && completedSteps_ == 0 && opts_.initial != InitialState::Rest;
  fem::StepState accepted = cs.disc_->step();  // the coarse level at this level's accepted load and time
  accepted.load = disc_->step().load;
  accepted.time = disc_->step().time - dt;
  accepted.dt = dynamic ? dt : 0.0;
  accepted.prediction = nullptr;
  PetscCall(cs.disc_->setStep(accepted));
  PetscCall(restrictTo(c, xPrev_, true, cs.x_));
  if (dynamic) {
    PetscCall(restrictTo(c, vPrev_, false, cs.v_));
    PetscCall(restrictTo(c, a_, false, cs.a_));  // its -predictor_acceleration extrapolates this level's a_n
    cs.haveAccel_ = haveAccel_;
    cs.velocityIsMotion_ = velocityIsMotion_;
  }
  cs.currentStep_ = currentStep_;
  cs.coarseWork_ = NewtonResult();
  NewtonResult r;
  bool ok = false;
  std::string reason;
  if (fromSynthetic && cs.opts_.detachedStart && !cs.nestedStep(currentStep_)) PetscCall(cs.detachedStart(&r));
  PetscCall(cs.advance(dt, loadTarget, 0, &r, &ok, &reason));
  for (auto &h : r.history) h.level = cs.level_;
  coarseWork_ += cs.coarseWork_;
  coarseWork_ += r;
  if (!ok) PetscFunctionReturn(0);

  // The coarse displacement (synthetic start) or correction, interpolated to this level's vertices.
  std::vector<double> coarseField, fineField;
  PetscCall(vertexField(*cs.disc_, cs.x_, true, &coarseField));
  if (!fromSynthetic) {
    std::vector<double> start, restricted;
    PetscCall(vertexField(*disc_, x_, true, &start));
    PetscCall(c.fromFine.interpolate(start, &restricted));
    for (size_t k = 0; k < coarseField.size(); ++k) coarseField[k] -= restricted[k];
  }
  PetscCall(c.toFine.interpolate(coarseField, &fineField));
  Vec candidate;
  PetscCall(VecDuplicate(x_, &candidate));
  if (fromSynthetic) PetscCall(disc_->restPositions(candidate));
  else PetscCall(VecCopy(x_, candidate));
  PetscCall(addVertexField(*disc_, fineField, candidate));

  // Both starts are judged at the step's load (the candidate carries the coarse solution's boundary motion): the
  // one Newton would take is this level's start with its Dirichlet vertices moved there. Taken, the load stays
  // (the safeguard's check of the move is the candidate's own); not taken, it goes back.
  std::vector<double> reference;
  PetscCall(newton_.alphasAt(x_, &reference));
  const double load = disc_->load();
  PetscCall(setLoad(loadTarget));
  PetscReal eStart, eCandidate;
  PetscCall(newton_.energyAt(x_, &eStart, nullptr));
  PetscCall(newton_.energyAt(candidate, &eCandidate, nullptr));
  bool acceptable = false;
  if (eCandidate < eStart) PetscCall(newton_.alphaAcceptable(candidate, reference, &acceptable));  // (NaN: never)
  if (acceptable) {
    PetscCall(VecCopy(candidate, x_));
    *used = true;
  } else {
    PetscCall(setLoad(load));
  }
  PetscCall(VecDestroy(&candidate));
  PetscFunctionReturn(0);
}

}  // namespace aries::solver
