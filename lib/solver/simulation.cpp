#include "solver/simulation.hpp"

#include "solver/coarse_level.hpp"

#include "core/options.hpp"
#include "solver/solver_options.hpp"
#include "preprocess/tutte.hpp"

#include <cmath>
#include <cstdint>

namespace aries::solver {

namespace {

constexpr PetscInt kMaxLoadSubsteps = 200;  // per step; beyond that the motion is reported as not followable

// Counter-based random numbers: the same value for a (seed, vertex, component) on any number of ranks.
double uniform01(uint64_t seed, uint64_t vertex, uint64_t component) {
  uint64_t z = seed * 0x9E3779B97F4A7C15ULL ^ (vertex * 0xBF58476D1CE4E5B9ULL + component * 0x94D049BB133111EBULL);
  z += 0x9E3779B97F4A7C15ULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * 0x1.0p-53;
}

}  // namespace

PetscErrorCode readSimulationOptions(SimulationOptions *o) {
  PetscBool set;
  PetscFunctionBeginUser;
  PetscCall(core::getChoice(opt::integrator, &o->integrator));
  PetscCall(core::get(opt::dt, &o->dt));
  PetscCall(core::get(opt::steps, &o->steps));
  PetscCall(core::getChoice(opt::initial, &o->initial));
  if (o->initial == InitialState::Scramble) {
    PetscCall(core::get(opt::scrambleVolumeRatio, &o->scrambleVolumeRatio));
    PetscCall(core::get(opt::scrambleSeed, &o->scrambleSeed));
  }
  if (o->integrator == Integrator::Static) {  // applies to synthetic starts only (not rest, tutte or a restart)
    PetscBool detached = PETSC_TRUE, shapeFirst = PETSC_TRUE;
    PetscCall(core::get(opt::detachedStart, &detached, &set));
    o->detachedStart = detached && syntheticStart(o->initial);
    PetscCall(core::get(opt::detachedShapeFirst, &shapeFirst, &set));
    o->detachedShapeFirst = shapeFirst;
  }
  if (o->integrator == Integrator::BackwardEuler) {
    PetscBool ps = PETSC_TRUE;
    PetscCall(core::get(opt::predictorStart, &ps));
    o->predictorStart = ps;
    if (ps) {
      PetscBool pa = PETSC_TRUE;
      PetscCall(core::get(opt::predictorAcceleration, &pa));
      o->predictorAcceleration = pa;
    }
    PetscCall(core::get(opt::beulerShapeFirst, &o->beulerShapeFirst));
    if (o->beulerShapeFirst > 0.0) PetscCall(core::get(opt::beulerShapeFirstTol, &o->beulerShapeFirstTol));
  }
  PetscBool nested = PETSC_FALSE;
  PetscCall(core::get(opt::coarseMesh, &o->coarseMeshes, &nested));
  if (nested)
    PetscCall(core::get(opt::coarseSteps, &o->coarseSteps, nullptr,
                        {nullptr, o->integrator == Integrator::Static ? "static" : "beuler"}));
  PetscCall(core::getChoice(opt::onFailure, &o->onFailure));
  if (o->onFailure == FailurePolicy::HalveDt) PetscCall(core::get(opt::maxStepHalvings, &o->maxStepHalvings));
  PetscCall(readNewtonOptions(o->integrator == Integrator::BackwardEuler, nullptr, nullptr, &o->newton));
  PetscFunctionReturn(0);
}

Simulation::Simulation() = default;

Simulation::~Simulation() {
  for (Vec *v : {&x_, &v_, &xPrev_, &vPrev_, &xTilde_, &a_, &xTry_})
    if (*v) VecDestroy(v);
}

PetscErrorCode Simulation::setup(fem::Discretization &disc, const SimulationOptions &opts) {
  MPI_Comm comm;
  PetscFunctionBeginUser;
  disc_ = &disc;
  opts_ = opts;
  PetscCall(PetscObjectGetComm((PetscObject)disc.dm(), &comm));
  const bool dynamic = opts.integrator == Integrator::BackwardEuler;
  const bool degenerateTetStart = degenerateDynamicStart(opts) && disc.mesh().shape == energies::ElementShape::Tet;
  opts_.newton.fiberDegenerateStart = degenerateTetStart && disc.anyFiberTerms();
  // known only now that the materials are: the case of -newton_forcing's default (kDegenerateStartForcing)
  if (degenerateTetStart && (disc.anyFiberTerms() || disc.anyVolumeTerms())) {
    PetscBool forcingGiven = PETSC_FALSE;
    PetscCall(core::get(opt::newtonForcing, &opts_.newton.convergence.forcing, &forcingGiven,
                        {nullptr, opt::kDegenerateStartForcing}));
    if (!forcingGiven)
      PetscCall(PetscPrintf(comm, "aries: inexact Newton, -newton_forcing %g (backward Euler from a degenerate start "
                                  "with fiber terms or a volume term (nu > 0); -newton_forcing 0 solves every "
                                  "direction to -ksp_rtol)\n",
                            opts_.newton.convergence.forcing));
  }
  PetscCall(newton_.setup(disc, opts_.newton, dynamic, opts.dt));
  PetscCall(DMCreateGlobalVector(disc.dm(), &x_));
  PetscCall(PetscObjectSetName((PetscObject)x_, "positions"));
  for (Vec *v : {&v_, &xPrev_, &vPrev_, &xTilde_}) PetscCall(VecDuplicate(x_, v));
  if (dynamic) {  // the last step's acceleration and the extrapolated start: backward Euler only (startFromPrediction)
    for (Vec *v : {&a_, &xTry_}) PetscCall(VecDuplicate(x_, v));
    PetscCall(VecSet(a_, 0.0));
  }
  PetscCall(VecSet(v_, 0.0));
  PetscCall(disc.restPositions(x_));
  fem::StepState start;
  start.dt = dynamic ? opts.dt : 0.0;
  PetscCall(disc.setStep(start));
  PetscCall(applyInitialState());
  syntheticStart_ = syntheticStart(opts_.initial);
  // read where it applies: the materials are known from here on (advance)
  if (dynamic && syntheticStart_ && opts_.beulerShapeFirst > 0.0 && disc.anyFiberTerms())
    PetscCall(core::getChoice(opt::beulerStartProjection, &opts_.beulerStartProjection));
  PetscCall(PetscLogStageGetId("solve", &solveStage_));
  if (solveStage_ < 0) PetscCall(PetscLogStageRegister("solve", &solveStage_));
  PetscCall(setupCoarseLevels());
  PetscFunctionReturn(0);
}

PetscErrorCode Simulation::applyInitialState() {
  MPI_Comm comm;
  PetscFunctionBeginUser;
  if (opts_.initial == InitialState::Rest) PetscFunctionReturn(0);
  PetscCall(PetscObjectGetComm((PetscObject)x_, &comm));
  if (opts_.initial == InitialState::Tutte) {
    std::vector<Eigen::Vector2d> uv;
    PetscCall(fem::tutteEmbedding(disc_->mesh(), &uv));
    if (disc_->dofsPerVertex() != 2)
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "-initial tutte makes a 2D map: use it with -uv_map");
    PetscInt lo;
    PetscScalar *xa;
    PetscCall(VecGetOwnershipRange(x_, &lo, nullptr));
    PetscCall(VecGetArray(x_, &xa));
    disc_->kinematics().forEachOwnedFreeVertex([&](PetscInt local, PetscInt, const PetscInt *rows, const Eigen::Vector3d &) {
      for (int i = 0; i < 2; ++i)
        if (rows[i] >= 0) xa[rows[i] - lo] = uv[local][i];
    });
    PetscCall(VecRestoreArray(x_, &xa));
    PetscFunctionReturn(0);
  }
  const int R = static_cast<int>(disc_->dofsPerVertex());
  // Rest centroid and measure of the body (vertices are the free ones; the centroid uses all cells).
  core::CentroidAccumulator acc;
  disc_->kinematics().forEachOwnedFreeVertex([&](PetscInt, PetscInt, const PetscInt *, const Eigen::Vector3d &X) { acc.add(X); });
  Eigen::Vector3d centroid;
  PetscCall(acc.reduce(comm, &centroid));
  PetscInt lo;
  PetscScalar *x;
  PetscCall(VecGetOwnershipRange(x_, &lo, nullptr));
  PetscCall(VecGetArray(x_, &x));
  if (opts_.initial == InitialState::Invert) {
    disc_->kinematics().forEachOwnedFreeVertex([&](PetscInt, PetscInt, const PetscInt *rows, const Eigen::Vector3d &X) {
      for (int i = 0; i < R; ++i)
        if (rows[i] >= 0) x[rows[i] - lo] = 2.0 * centroid[i] - X[i];
    });
  } else if (opts_.initial == InitialState::CollapsePlane || opts_.initial == InitialState::CollapseLine ||
             opts_.initial == InitialState::CollapsePoint) {
    // Stress tests: the coordinates from `keep` on are set to the centroid's (plane: the last coordinate, so every
    // free vertex lies in the plane through the centroid normal to z (y in 2D); line: all but x; point: all).
    const int keep = opts_.initial == InitialState::CollapsePlane ? R - 1
                     : opts_.initial == InitialState::CollapseLine ? 1 : 0;
    disc_->kinematics().forEachOwnedFreeVertex([&](PetscInt, PetscInt, const PetscInt *rows, const Eigen::Vector3d &X) {
      for (int i = 0; i < R; ++i)
        if (rows[i] >= 0) x[rows[i] - lo] = i < keep ? X[i] : centroid[i];
    });
  } else {
    const int dim = disc_->shapeCols() == 3 ? 3 : 2;
    const double side = std::pow(opts_.scrambleVolumeRatio * disc_->restMeasureGlobal(), 1.0 / dim);
    const uint64_t seed = static_cast<uint64_t>(opts_.scrambleSeed);
    disc_->kinematics().forEachOwnedFreeVertex([&](PetscInt, PetscInt natural, const PetscInt *rows, const Eigen::Vector3d &) {
      for (int i = 0; i < R; ++i) {
        const bool inPlane = i < dim;
        if (rows[i] >= 0) x[rows[i] - lo] = centroid[i] + (inPlane ? side * (uniform01(seed, natural, i) - 0.5) : 0.0);
      }
    });
  }
  PetscCall(VecRestoreArray(x_, &x));
  PetscFunctionReturn(0);
}

PetscErrorCode Simulation::resume(const std::vector<double> &positions, const std::vector<double> &velocities,
                                  const std::vector<double> &accelerations, bool velocityIsMotion,
                                  PetscInt completedStep, double time, double load, const NewtonMemory &memory) {
  PetscFunctionBeginUser;
  const int R = static_cast<int>(disc_->dofsPerVertex());
  haveAccel_ = a_ && !accelerations.empty();  // a static run has none (and no a_)
  velocityIsMotion_ = velocityIsMotion;
  PetscInt lo;
  PetscScalar *x, *v, *a = nullptr;
  PetscCall(VecGetOwnershipRange(x_, &lo, nullptr));
  PetscCall(VecGetArray(x_, &x));
  PetscCall(VecGetArray(v_, &v));
  if (a_) PetscCall(VecGetArray(a_, &a));
  disc_->kinematics().forEachOwnedFreeVertex([&](PetscInt local, PetscInt, const PetscInt *rows, const Eigen::Vector3d &) {
    for (int i = 0; i < R; ++i)
      if (rows[i] >= 0) {
        const size_t k = 3 * static_cast<size_t>(local) + i;
        x[rows[i] - lo] = positions[k];
        v[rows[i] - lo] = velocities[k];
        if (a) a[rows[i] - lo] = haveAccel_ ? accelerations[k] : 0.0;
      }
  });
  PetscCall(VecRestoreArray(x_, &x));
  PetscCall(VecRestoreArray(v_, &v));
  if (a_) PetscCall(VecRestoreArray(a_, &a));
  fem::StepState resumed = disc_->step();
  resumed.load = load;
  resumed.time = time;
  PetscCall(disc_->setStep(resumed));
  completedSteps_ = completedStep;
  syntheticStart_ = false;
  time_ = time;
  newton_.restore(memory);
  PetscFunctionReturn(0);
}

PetscErrorCode Simulation::localState(Vec xLocal) const {
  PetscFunctionBeginUser;
  PetscCall(DMGlobalToLocal(disc_->dm(), x_, INSERT_VALUES, xLocal));
  PetscCall(disc_->fillBoundary(xLocal));
  PetscFunctionReturn(0);
}

PetscErrorCode Simulation::localVelocity(Vec vLocal) const {
  PetscFunctionBeginUser;
  PetscCall(VecZeroEntries(vLocal));
  PetscCall(DMGlobalToLocal(disc_->dm(), v_, INSERT_VALUES, vLocal));
  PetscFunctionReturn(0);
}

PetscErrorCode Simulation::localAcceleration(Vec aLocal) const {
  PetscFunctionBeginUser;
  PetscCall(VecZeroEntries(aLocal));
  if (a_) PetscCall(DMGlobalToLocal(disc_->dm(), a_, INSERT_VALUES, aLocal));  // static runs: zero
  PetscFunctionReturn(0);
}

// Backward Euler (-predictor_start, on by default): Newton starts from the prediction x~ = x_n + dt v_n (the minimizer
// of the inertia term) instead of x_n when that is a better start: its total potential is lower and every alpha stays
// acceptable (the safeguard's rule); an infinite energy (a vertex inside an obstacle, an element at alpha <= 0 under
// the barrier) rules it out. With -predictor_acceleration (on by default) the extrapolation of the last step's
// acceleration, x^ = x~ + dt^2 a_n, is a third candidate: backward Euler's solution is x_n + dt v_n + dt^2 a_{n+1}, so
// where the motion's acceleration changes little from step to step (a body swinging or vibrating, supports or shape
// targets following a smooth path; free fall, where it is exact) x^ is much closer to it than x~ (the Fig. 13
// interaction on the 24.9k-hex bunny: 1.01 Newton updates per step against 1.50; bench/results/
// newton_work_predictor.md). The lowest potential among the candidates below x_n's that the safeguard accepts is
// taken. Energies at the previous load; the load increment follows in solveToLoad.
PetscErrorCode Simulation::startFromPrediction() {
  PetscFunctionBeginUser;
  struct Candidate {
    Vec x;
    PetscReal energy;
  };
  PetscReal eCur;
  Candidate prediction{xTilde_, 0.0}, extrapolated{xTry_, PETSC_INFINITY};
  PetscCall(newton_.energyAt(x_, &eCur, nullptr));
  PetscCall(newton_.energyAt(xTilde_, &prediction.energy, nullptr));
  if (opts_.predictorAcceleration && haveAccel_) {
    const double dt = disc_->step().dt;
    PetscCall(VecWAXPY(xTry_, dt * dt, a_, xTilde_));
    PetscCall(newton_.energyAt(xTry_, &extrapolated.energy, nullptr));
  }
  Candidate order[2] = {prediction, extrapolated};
  if (extrapolated.energy < prediction.energy) std::swap(order[0], order[1]);
  std::vector<double> ref;
  // -info names the start each step took and the candidates the safeguard turned down (docs/options.md)
  const auto label = [this](const Candidate &c) { return c.x == xTilde_ ? "x~" : "x~ + dt^2 a_n"; };
  const char *taken = "x_n";
  for (const Candidate &c : order) {
    if (!(c.energy < eCur)) continue;  // NaN and infinite energies too
    if (ref.empty()) PetscCall(newton_.alphasAt(x_, &ref));
    bool ok = false;
    PetscCall(newton_.alphaAcceptable(c.x, ref, &ok));
    if (!ok) {
      PetscCall(PetscInfo(nullptr, "step %" PetscInt_FMT " start: %s rejected by the alpha safeguard\n",
                          completedSteps_ + 1, label(c)));
      continue;
    }
    PetscCall(VecCopy(c.x, x_));
    taken = label(c);
    break;
  }
  PetscCall(PetscInfo(nullptr,
                      "step %" PetscInt_FMT " start: %s (potential x_n %.10g, x~ %.10g, x~ + dt^2 a_n %.10g)\n",
                      completedSteps_ + 1, taken, (double)eCur, (double)prediction.energy, (double)extrapolated.energy));
  PetscFunctionReturn(0);
}

// Moves the prescribed motion of the step being solved for to load parameter s.
PetscErrorCode Simulation::setLoad(double s) {
  PetscFunctionBeginUser;
  fem::StepState step = disc_->step();
  step.load = s;
  PetscCall(disc_->setStep(step));
  PetscFunctionReturn(0);
}

PetscErrorCode Simulation::moveSupportsAlone(double loadTarget, PetscInt halvings, bool *moved) {
  PetscFunctionBeginUser;
  const double s0 = disc_->load();
  std::vector<double> ref;
  PetscCall(newton_.alphasAt(x_, &ref));
  *moved = false;
  double sTry = loadTarget;
  for (PetscInt k = 0; k <= halvings && !*moved; ++k) {
    if (k > 0) sTry = s0 + 0.5 * (sTry - s0);
    PetscCall(setLoad(sTry));
    PetscCall(newton_.alphaAcceptable(x_, ref, moved));
  }
  if (!*moved) PetscCall(setLoad(s0));
  PetscFunctionReturn(0);
}

// Newton solves from the current state to the prescribed load `loadTarget`. With -lift_increments (the default) the
// increment enters the solve (NewtonSolver::solve with a target, lifted_increment.cpp): one solve per step unless the
// safeguard kept shortening its lifted updates (the rest of the increment is then another solve from the load reached,
// a load sub-step). Where no lifted update can be accepted at all, and without -lift_increments, the supports move
// alone: the increment is halved until moving them keeps every alpha acceptable, and each part is a Newton solve.
PetscErrorCode Simulation::solveToLoad(double loadTarget, NewtonResult *acc, bool *ok, std::string *reason) {
  PetscFunctionBeginUser;
  *ok = true;
  for (PetscInt sub = 0;; ++sub) {
    const double s0 = disc_->load();
    if (sub >= kMaxLoadSubsteps) {  // the motion is not followable within the safeguard
      *ok = false;
      *reason = "safeguard_load";
      PetscFunctionReturn(0);
    }
    // Backward Euler under -lift_increments auto: the supports move alone where the safeguard accepts that move (as
    // without lifting); only a move it rejects is lifted (NewtonSolver::supportsAloneFirst).
    bool movedAlone = false;
    if (s0 != loadTarget && newton_.supportsAloneFirst()) PetscCall(moveSupportsAlone(loadTarget, 0, &movedAlone));
    if (s0 != loadTarget && !movedAlone) {
      NewtonResult r;
      bool advanced = false;
      PetscCall(PetscLogStagePush(solveStage_));
      PetscCall(newton_.solve(x_, loadTarget, &r, &advanced));
      PetscCall(PetscLogStagePop());
      *acc += r;
      if (advanced) {
        *reason = reasonName(*acc);
        if (!r.converged()) {
          *ok = false;
          PetscFunctionReturn(0);
        }
        if (disc_->load() == loadTarget) break;
        ++loadSubsteps_;
        continue;
      }
    }
    if (loadTarget != s0 && !movedAlone) {
      bool acceptable = false;
      PetscCall(moveSupportsAlone(loadTarget, opts_.maxLoadHalvings, &acceptable));
      // No increment of the prescribed motion keeps every alpha acceptable: the boundary motion cannot be followed
      // within the safeguard.
      if (!acceptable) {
        *ok = false;
        *reason = "safeguard_load";
        PetscFunctionReturn(0);
      }
      if (disc_->load() != loadTarget) ++loadSubsteps_;
    }
    NewtonResult r;
    PetscCall(PetscLogStagePush(solveStage_));
    PetscCall(newton_.solve(x_, &r));
    PetscCall(PetscLogStagePop());
    *acc += r;
    *reason = reasonName(*acc);  // the step's: converged_initial only if nothing in it updated the state
    if (!r.converged()) {
      *ok = false;
      PetscFunctionReturn(0);
    }
    if (disc_->load() == loadTarget) break;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode Simulation::advance(double dt, double loadTarget, int depth, NewtonResult *acc, bool *ok,
                                   std::string *reason) {
  const bool dynamic = opts_.integrator == Integrator::BackwardEuler;
  PetscFunctionBeginUser;
  // The trial step: the accepted state's load (the load increment follows in solveToLoad), time-dependent material
  // data (keyframed shape targets) at the step's end, and for backward Euler dt and the prediction. A failed attempt
  // hands `accepted` back.
  const fem::StepState accepted = disc_->step();
  fem::StepState trial = accepted;
  trial.time = accepted.time + dt;
  PetscCall(VecCopy(x_, xPrev_));
  PetscCall(VecCopy(v_, vPrev_));
  if (dynamic) {
    trial.dt = dt;
    PetscCall(newton_.setTimeStep(dt));
    PetscCall(VecWAXPY(xTilde_, dt, v_, x_));  // x~ = x_n + dt v_n
    trial.prediction = xTilde_;
  }
  PetscCall(disc_->setStep(trial));
  if (dynamic && opts_.predictorStart) PetscCall(startFromPrediction());
  if (depth == 0 && nestedStep(currentStep_)) {  // the first attempt of the step, not its halves
    bool used = false;
    PetscCall(startFromCoarse(dt, loadTarget, &used));
    coarseStart_ = used ? 1 : 0;
    if (!used && currentStep_ == 1 && completedSteps_ == 0 && opts_.detachedStart) PetscCall(detachedStart(acc));
  }
  {
    Vec xLocal;
    PetscInt fallback = 0;
    PetscCall(DMGetLocalVector(disc_->dm(), &xLocal));
    PetscCall(localState(xLocal));
    PetscInt active = 0;
    PetscCall(disc_->updateBarrierFallback(xLocal, std::max(newton_.alphaMin(), 0.0), &fallback));
    PetscCall(disc_->barrierActiveCells(xLocal, &active));
    PetscCall(DMRestoreLocalVector(disc_->dm(), &xLocal));
    acc->barrierFallbackCells = std::max(acc->barrierFallbackCells, fallback);
    acc->barrierActiveCells = std::max(acc->barrierActiveCells, active);
  }
  // A synthetic start dominated by volume terms: the stretch terms first (shape_first.cpp). Later steps start from a
  // converged state moved by one step of inertia-limited motion and are not checked (two energy evaluations a step).
  // Not with fiber terms: there the stage did not help (fiber along x at nu 0.3: 220 updates against 126, the same
  // time) or hurt (an oblique fiber: step 1 past 240 s against 54 s for two steps; bench/degenerate_starts.py).
  // With fiber terms the run filters by -beuler_start_psd_projection instead (default abs), from step 1 to its end:
  // clamped, a scrambled body's Hessians leave the inverted cells' modes to the mass term alone, which the volume
  // term's curvatures outgrow by orders of magnitude, and CG stalls at -ksp_max_it (fiber along x at nu 0.3, camel:
  // step 1 took 126 updates, 42 solves at the limit, 41 s; abs: 68, none, 10 s; bench/results/
  // degenerate_starts_fiber_filter.md). The body stays far from rest for several steps, with starts that no longer
  // pass the ratio test (hand, same energy, seed 1: step 2 had not ended after 180 s clamped; abs 160 updates, 50 s),
  // and where no Hessian has negative eigenvalues the two filters agree. Not after the shape stage: there abs lost in a
  // trial by hand (iarap at nu 0.3, hand, seed 1, 2 ranks: 91 updates against 56; camel and triceratops about even).
  if (dynamic && syntheticStart_ && opts_.beulerShapeFirst > 0.0) {
    if (!disc_->anyFiberTerms()) {
      PetscCall(PetscLogStagePush(solveStage_));
      PetscCall(solveShapeFirst(*disc_, newton_, x_, opts_.beulerShapeFirst, opts_.beulerShapeFirstTol, acc));
      PetscCall(PetscLogStagePop());
    } else {
      bool dominated = false;
      PetscCall(volumeDominated(*disc_, x_, opts_.beulerShapeFirst, &dominated));
      if (dominated) newton_.overrideFilter(opts_.beulerStartProjection);  // for the rest of the run
    }
  }
  const bool fromSyntheticState = syntheticStart_;  // its velocity after the step is the recovery, not motion
  PetscCall(solveToLoad(loadTarget, acc, ok, reason));
  if (*ok) {
    acc->mollifierBandCells = 0;  // a half step that recovered a failed attempt: nothing held
    syntheticStart_ = false;
    if (dynamic) {
      PetscCall(VecWAXPY(v_, -1.0, xPrev_, x_));
      PetscCall(VecScale(v_, 1.0 / dt));
      PetscCall(VecWAXPY(a_, -1.0, vPrev_, v_));  // a_{n+1} = (v_{n+1} - v_n) / dt
      PetscCall(VecScale(a_, 1.0 / dt));
      haveAccel_ = velocityIsMotion_ && !fromSyntheticState;  // v_n and v_{n+1} both the body's motion
      velocityIsMotion_ = !fromSyntheticState;
    }
    PetscFunctionReturn(0);
  }
  {  // where the failed solve stopped: cells held at the mollifier's band (the console's hint)
    Vec xLocal;
    PetscInt band = 0;
    PetscCall(DMGetLocalVector(disc_->dm(), &xLocal));
    PetscCall(localState(xLocal));
    PetscCall(disc_->mollifierBandCells(xLocal, &band));
    PetscCall(DMRestoreLocalVector(disc_->dm(), &xLocal));
    acc->mollifierBandCells = band;
  }
  if (opts_.onFailure == FailurePolicy::HalveDt && depth < opts_.maxStepHalvings) {
    const std::string failed = *reason;
    PetscCall(VecCopy(xPrev_, x_));
    PetscCall(VecCopy(vPrev_, v_));
    PetscCall(disc_->setStep(accepted));
    const double mid = 0.5 * (accepted.load + loadTarget);
    PetscCall(advance(0.5 * dt, mid, depth + 1, acc, ok, reason));
    if (*ok) PetscCall(advance(0.5 * dt, loadTarget, depth + 1, acc, ok, reason));
    if (dynamic) PetscCall(newton_.setTimeStep(opts_.dt));
    // The stats keep why the step was split: "<final reason>|halved:<failure>" (nested halvings keep the first).
    if (reason->find("|halved:") == std::string::npos) *reason += "|halved:" + failed;
    PetscFunctionReturn(0);
  }
  if (opts_.onFailure == FailurePolicy::Continue) {
    PetscReal nrm;
    PetscCall(VecNorm(x_, NORM_INFINITY, &nrm));
    if (!std::isfinite(nrm)) {  // keep the last finite state
      PetscCall(VecCopy(xPrev_, x_));
      PetscCall(VecCopy(vPrev_, v_));
    } else if (dynamic) {
      PetscCall(VecWAXPY(v_, -1.0, xPrev_, x_));
      PetscCall(VecScale(v_, 1.0 / dt));
    }
    haveAccel_ = velocityIsMotion_ = false;  // an unconverged step's motion is not extrapolated
    PetscCall(setLoad(loadTarget));
    PetscFunctionReturn(0);
  }
  // Stop: restore the last accepted state so the output is a valid state.
  PetscCall(VecCopy(xPrev_, x_));
  PetscCall(VecCopy(vPrev_, v_));
  PetscCall(disc_->setStep(accepted));
  PetscFunctionReturn(0);
}

PetscErrorCode Simulation::run(StepObserver *observer, RunSummary *summary) {
  PetscFunctionBeginUser;
  PetscCall(VecGetSize(x_, &summary->dofs));
  const PetscInt steps = opts_.steps;
  const PetscInt ramp = disc_->boundary().rampSteps > 0 ? disc_->boundary().rampSteps : steps;
  if (observer && completedSteps_ == 0) PetscCall(observer->initial(*this));
  double totalNewton = 0, totalLinear = 0, totalSeconds = 0;
  const PetscInt first = completedSteps_ + 1;
  summary->firstStep = first;
  // Step times from the run's start (0, or the restart point) as start + k dt, not a running sum: after 50 steps of
  // 1e-2 the time is 0.5, not 0.49999999999999994.
  const double startTime = time_;
  for (PetscInt step = first; step <= steps; ++step) {
    const double t0 = MPI_Wtime();
    const double loadTarget = std::min(1.0, static_cast<double>(step) / static_cast<double>(ramp));
    StepReport rep;
    rep.step = step;
    rep.steps = steps;
    rep.time = startTime + static_cast<double>(step - first + 1) * opts_.dt;
    currentStep_ = step;
    coarseWork_ = NewtonResult();
    coarseStart_ = -1;
    if (step == 1 && opts_.detachedStart && !nestedStep(step)) PetscCall(detachedStart(&rep.newton));
    PetscCall(advance(opts_.dt, loadTarget, 0, &rep.newton, &rep.ok, &rep.reason));
    rep.coarse = coarseWork_;
    rep.coarseStart = coarseStart_;
    time_ = rep.time;
    completedSteps_ = step;
    rep.wallSeconds = MPI_Wtime() - t0;
    rep.stopping = step == steps || (!rep.ok && opts_.onFailure == FailurePolicy::Stop);
    totalNewton += rep.newton.newtonIterations;
    totalLinear += rep.newton.linearIterations;
    summary->coarseNewton += rep.coarse.newtonIterations;
    summary->coarseLinear += rep.coarse.linearIterations;
    totalSeconds += rep.wallSeconds;
    summary->assemblySeconds += rep.newton.assemblySeconds;
    summary->stepsDone = step;
    summary->safeguardHalvings += rep.newton.safeguardHalvings;
    summary->lastReason = rep.reason;
    if (!rep.ok) ++summary->failedSteps;
    if (observer) PetscCall(observer->afterStep(*this, rep));
    if (!rep.ok && opts_.onFailure == FailurePolicy::Stop) {
      summary->failed = true;
      break;
    }
  }
  const double n = std::max<PetscInt>(1, summary->stepsDone - first + 1);
  summary->avgNewton = totalNewton / n;
  summary->avgLinear = totalLinear / n;
  summary->avgSeconds = totalSeconds / n;
  summary->coarseNewton /= n;
  summary->coarseLinear /= n;
  summary->nested = static_cast<bool>(coarse_);
  summary->totalSeconds = totalSeconds;
  summary->loadSubsteps = loadSubsteps_;
  PetscFunctionReturn(0);
}

}  // namespace aries::solver
