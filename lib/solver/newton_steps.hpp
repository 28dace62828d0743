// The strategies of the projected Newton solver (newton.hpp), each an object with its own options
// (newton_options.hpp) and state, run by NewtonSolver in this order on every direction, before the line search:
//
//   1. RigidMotionRemoval  a floating body (the detached start): the direction's rigid-motion share is removed
//   2. ConvergenceCheck    the convergence test on the Newton direction (paper Sec. 6), the step bound of backward
//                          Euler, the inexact linear solve's stop (-newton_tol, -newton_forcing)
//   3. SubspaceStep        the exact quadratic model minimized over the direction and the last updates
//                          (-newton_subspace, -newton_subspace_max)
//   4. RotationalUpdate    rotational parts of the step follow the circle (-newton_rotation)
//   5. HessianFilter       the element Hessians' eigenvalue filter; the adaptive one's curvature of the update and
//                          its choice after it; the unfiltered system after a full-length update (-psd_projection,
//                          -psd_eigensystem, -psd_adaptive_tol, -newton_exact_hessian)
//   6. AlphaSafeguard      no step takes a guarded element's alpha below -alpha_min (paper Sec. 4.2)
//
// Before all of them the filter checks that an unfiltered system was positive definite (repairDirection: otherwise it
// is solved again filtered). A step's increment of the prescribed motion is carried by the lifted updates before the
// SNES iteration (lifted_increment.cpp), which the safeguard guards and the filter follows. A direction the
// convergence check accepts is the step's final correction: only the steps that apply to one run
// on it (the safeguard); a converged direction (a short Newton step, or one accepted by round-off) is applied only
// where it lowers |g|, and nothing runs after the check. After each line
// search every step may pull the accepted point back (checkPoint, the safeguard); after each update every step
// sees its length (finishUpdate: the subspace step's limit, the adaptive filter's choice).
// Steps that do nothing under the options are not created: the chain is the set of strategies a solve runs.
#pragma once

#include "fem/discretization.hpp"
#include "solver/convergence_rule.hpp"
#include "solver/local_vec.hpp"
#include "solver/newton_options.hpp"
#include "solver/preconditioner_reuse.hpp"

#include <petscsnes.h>

#include <vector>

namespace aries::solver {

// What a Newton solver carries from one solve to the next: the Hessian filter's back-off after failed unfiltered
// systems (-newton_exact_hessian) and a filter that overrides the run's (NewtonSolver::overrideFilter). Checkpoints
// keep it (io/checkpoint.hpp).
struct NewtonMemory {
  int filterBackoff = 0;    // solves kept filtered after the next failure / 2 (0: none failed lately)
  int filterSkip = 0;       // solves left that keep the filter
  int filterOverride = -1;  // an EigenFilterMode that overrides -psd_projection's (-1: none)
  int filterExactStart = 0; // 1: the last solve's unfiltered systems were all definite (-newton_exact_start)
};

// One Newton iteration, for -newton_history and the convergence charts.
struct IterationRecord {
  PetscInt iteration = 0;
  double energy = 0.0;      // total potential at the iterate
  double residual = 0.0;    // |gradient|_2 over the free dofs
  double stepInf = 0.0;     // |Newton step|_inf (before acceleration and line search)
  double lambda = 0.0;      // length of the step applied from this iterate: the line search's, or the final
                            // correction's on a converged row (1, halved by the safeguard); 0: nothing applied
  PetscInt linearIterations = 0;
  char filter = 'c';        // element Hessian filter of this iteration: c(lamp), a(bs), n(one)
  bool accelerated = false; // the update used the subspace step
  double rotation = 0.0;    // the rotational update's angle scale (1, 2, 4, ...; 0: plain direction)
  int level = 0;            // nested iteration: 0 the run's mesh, k the k-th -coarse_mesh
  double load = 0.0;        // the load parameter of the state the row's update reached (its target, once reached)
  bool lifted = false;      // a lifted update: the supports moved with it (lifted_increment.cpp)
  double extrapolated = 0.0;  // -newton_extrapolate's scale of the full step (2, 4, ...; 0: not extrapolated)
  bool firstOfSolve = false;  // the first row of a Newton solve (-newton_history's solve column counts them)
  bool preconditionerBuilt = true;  // its solve built the preconditioner (false: kept, -multigrid_reuse_growth)
};

struct NewtonResult {
  PetscInt newtonIterations = 0;   // updates of the state (line searches that moved it)
  PetscInt linearSolves = 0;       // Newton systems solved (one per direction, including the converging one)
  PetscInt linearIterations = 0;   // Krylov iterations over all of them
  PetscInt localIterations = 0;   // the local solves' Newton iterations (-newton_local_solve; not updates above)
  PetscInt linearAtLimit = 0;      // linear solves stopped by -ksp_max_it (their direction is not a Newton step)
  PetscInt safeguardHalvings = 0;
  SNESConvergedReason reason = SNES_CONVERGED_ITERATING;
  Convergence convergence = Convergence::None;
  PetscInt barrierFallbackCells = 0;  // cells evaluated with the mollifier in barrier mode (alpha ~ 0)
  PetscInt barrierActiveCells = 0;    // cells with an active aberration barrier (0 < alpha < eps) at the step start
  PetscInt mollifierBandCells = 0;    // a failed step: cells at the mollifier's band at its last iterate
                                      // (fem::Discretization::mollifierBandCells), set by Simulation::advance on
                                      // the step's result; += leaves it (a solve's own result never sets it)
  PetscReal residualNorm = 0.0;       // |gradient of the potential|_2 over the free dofs at the last iterate
  double assemblySeconds = 0.0;       // wall time in the model's energy, gradient, Hessian and curvature evaluations
  std::vector<IterationRecord> history;
  bool converged() const { return reason > 0; }
  NewtonResult &operator+=(const NewtonResult &o);  // sums the counters, keeps o's outcome, appends its history
};

// What every step shares: the model (discretization, SNES, Jacobian), the time step and the solve in progress.
struct NewtonContext {
  fem::Discretization *disc = nullptr;
  SNES snes = nullptr;
  Mat J = nullptr;
  Vec work = nullptr;     // scratch, free for any step between calls
  Vec trialX = nullptr;   // a trial point and its gradient (NewtonSolver::stepIfResidualDrops)
  Vec trialF = nullptr;
  Vec invMass = nullptr;  // backward Euler: 1 / m per free dof
  double minMass = 0.0;
  bool dynamic = false;
  double dt = 0.0;
  double stepTol = 0.0;   // the converged step's inf-norm
  bool inertiaGuess = false;  // -newton_inertia_guess: every linear solve starts from startFromInertia
  PetscInt iterationOffset = 0;  // updates of this solve before the SNES iteration (lifted ones): added to its count
  bool psdHessian = true; // the element Hessians are filtered to be PSD (the backward-Euler step bound needs it)
  PetscLogStage assemblyStage = -1;
  double assemblyStart = 0.0;
  NewtonResult result;    // the solve in progress
  PreconditionerReuse preconditioner;  // whether a Newton system builds its preconditioner (-multigrid_reuse_growth)

  PetscErrorCode energyAt(Vec x, PetscReal *value, PetscReal *magnitude);  // total potential at a global state
  // While a solve runs (NewtonSolver::solve keeps it on; its load changes clear it): energyAt remembers the last state
  // it evaluated (local values, boundary values included) and that state's potential. The convergence check asks for
  // the potential at the point the line search has just evaluated and accepted; within a solve only the load changes
  // the potential of a state, and outside one (the predictor and support tests between solves) nothing is remembered.
  struct EnergyMemo {
    bool on = false, valid = false;
    LocalStateKey state;
    PetscReal value = 0.0, magnitude = 0.0;
  } energyMemo;
  // Around every evaluation of the model: the "assembly" log stage (-log_view) and result.assemblySeconds.
  PetscErrorCode beginAssembly();
  PetscErrorCode endAssembly();
  // G_kl = d_k^T H d_l with the exact (unfiltered) Hessian at X.
  PetscErrorCode gram(Vec X, const std::vector<Vec> &directions, std::vector<double> *G);
  // Backward Euler's bound on |H^-1 g|_inf (infinite where none holds).
  PetscErrorCode stepBound(Vec g, PetscReal *bound);
  // Backward Euler's start of the linear solve H p = g (-newton_inertia_guess): p <- the inertia-only step, or 0.
  PetscErrorCode startFromInertia(Mat H, Vec g, Vec p);
  // After the KSP solved a Newton system H x = b: its outcome goes to `preconditioner`; a solve that failed with a
  // kept preconditioner (stopped at its iteration limit, or any failure but negative curvature, which is the
  // matrix's) is solved again from zero with a new one, counted as a solve of its own. The caller reads the KSP's
  // reason and iterations afterwards.
  PetscErrorCode finishSystem(KSP ksp, Vec b, Vec x);
  // H x = b solved with a preconditioner built for the KSP's matrix now (a filtered re-solve, or finishSystem's),
  // counted, its outcome to `preconditioner`.
  PetscErrorCode solveWithNewPreconditioner(KSP ksp, Vec b, Vec x);
  // A linear solve of the Newton solve in progress ended with `reason`: result.linearSolves and linearAtLimit.
  void countLinearSolve(KSPConvergedReason reason);
  void declareConverged(Convergence how);
};

// The direction of the iteration in progress, from the linear solve to the end of its line search. The line search
// steps from X to X - lambda Y; g . Y is the slope.
struct Direction {
  IterationRecord record;  // its iteration number included
  double energyBefore = 0.0;   // energy at X
  double slope = 0.0;          // g . Y
  double curvature = 0.0;      // Y^T H Y with the exact Hessian, when known
  bool haveCurvature = false;
  bool halved = false;         // the safeguard shortened it
  double postScale = 1.0;      // the share of the line search's length the safeguard kept
  bool finalCorrection = false;  // converged: the small step is applied without a line search if it lowers |g|
  double roundoff = 0.0;         // the energy's round-off at X (ConvergenceCheck)
  bool residualStep = false;     // flat (its energy change is round-off): taken because it lowers |g|, no line search
};

class NewtonStep {
 public:
  virtual ~NewtonStep() = default;
  virtual bool appliesToFinalCorrection() const { return false; }
  virtual PetscErrorCode beginSolve(NewtonContext &) { return 0; }
  // Before the line search: may change the direction Y (then *changed = true).
  virtual PetscErrorCode shapeDirection(NewtonContext &ctx, Direction &d, Vec X, Vec Y, Vec F, PetscBool *changed) = 0;
  // After the line search, on its accepted point W (may move it towards X).
  virtual PetscErrorCode checkPoint(NewtonContext &, Direction &, Vec /*X*/, Vec /*W*/, PetscBool * /*changed*/) {
    return 0;
  }
  // After an update of length lambda (the line search's times the safeguard's share) to xNew.
  virtual PetscErrorCode finishUpdate(NewtonContext &, const Direction &, Vec /*xNew*/, double /*lambda*/) {
    return 0;
  }
};

// 1. A body without supports: its energy is invariant under rigid motions, so the direction's rigid-motion share
// (which CG on the singular system leaves undetermined) is removed before the convergence test and the line search.
class RigidMotionRemoval final : public NewtonStep {
 public:
  PetscErrorCode shapeDirection(NewtonContext &ctx, Direction &d, Vec X, Vec Y, Vec F, PetscBool *changed) override;
};

// The -newton_history `filter` column of a system assembled with this eigenvalue filter: a(bs), c(lamp), n(one).
inline char filterTag(kernels::EigenFilter filter) {
  return filter == kernels::EigenFilter::Abs ? 'a' : filter == kernels::EigenFilter::None ? 'n' : 'c';
}

// Did the linear solve solve the Newton system? The trust-region CG variants (-ksp_type nash, stcg, gltr) report a
// truncated direction as converged (stopped at negative curvature or at the trust radius): a short direction from
// them says nothing about the distance to equilibrium (NASH stopped at its first iteration returns p = 0, which
// looked like a converged step), so it may still be searched along but never certifies convergence.
inline bool linearSolveSolved(KSPConvergedReason reason) {
  return reason > 0 && reason != KSP_CONVERGED_CG_NEG_CURVE && reason != KSP_CONVERGED_CG_CONSTRAINED &&
         reason != KSP_CONVERGED_STEP_LENGTH;
}

// 2. Is the state converged on the Newton direction? Also the convergence test at each iterate (backward Euler's
// step bound, certified without a linear solve) and the inexact linear solve's stop.
class ConvergenceCheck final : public NewtonStep {
 public:
  explicit ConvergenceCheck(const ConvergenceOptions &o) : opts_(o) {}
  ~ConvergenceCheck() override;
  PetscErrorCode setup(NewtonContext &ctx);  // after SNESSetFromOptions: the KSP's tolerance and test
  PetscErrorCode shapeDirection(NewtonContext &ctx, Direction &d, Vec X, Vec Y, Vec F, PetscBool *changed) override;
  // At iterate `it` whose residual g has norm fnorm: converged by the step bound? (sets *reason)
  PetscErrorCode testIterate(NewtonContext &ctx, PetscInt it, PetscReal fnorm, SNESConvergedReason *reason);
  PetscReal baseLinearRtol() const { return baseRtol_; }  // -ksp_rtol as set up (a certifying solve's)

 private:
  static PetscErrorCode linearTest(KSP, PetscInt, PetscReal, KSPConvergedReason *, void *);
  ConvergenceOptions opts_;
  NewtonContext *ctx_ = nullptr;
  PetscReal baseRtol_ = 1e-6;    // the linear solve's tolerance without forcing (certifying solves)
  void *defaultKspCtx_ = nullptr;
  double rnorm0_ = 0.0;          // reference of the linear solve's relative residual
  bool forcingStopped_ = false;  // the last linear solve stopped early
  bool forcingOn_ = true;        // off during a certifying solve
};

// 3. Subspace step: the update minimizes the true quadratic model (exact Hessian) over span{Newton direction, last
// m updates}.
class AlphaSafeguard;

class SubspaceStep final : public NewtonStep {
 public:
  // safeguard: the run's alpha safeguard, which the extrapolation asks before it doubles a step (not owned)
  SubspaceStep(const SubspaceOptions &o, AlphaSafeguard *safeguard) : opts_(o), safeguard_(safeguard) {}
  ~SubspaceStep() override;
  PetscErrorCode beginSolve(NewtonContext &ctx) override;
  PetscErrorCode shapeDirection(NewtonContext &ctx, Direction &d, Vec X, Vec Y, Vec F, PetscBool *changed) override;
  PetscErrorCode finishUpdate(NewtonContext &ctx, const Direction &d, Vec xNew, double lambda) override;

 private:
  PetscErrorCode extrapolate(NewtonContext &ctx, Direction &d, Vec X, Vec Y, PetscBool *changed);
  SubspaceOptions opts_;
  AlphaSafeguard *safeguard_;
  std::vector<double> alphaRef_;  // the alphas at the update's start, for the extrapolation's safeguard checks
  std::vector<Vec> updates_;  // previous updates of this solve, newest first
  Vec prevX_ = nullptr, newtonDir_ = nullptr;
  PetscInt count_ = 0;        // updates held
  bool lastFull_ = false;     // the previous update was a full, unshortened step
};

// 4. Rotational update: where the direction is locally a rotation, each vertex follows the circle by the same angle;
// up to K doublings of the angle are tried while the energy falls.
class RotationalUpdate final : public NewtonStep {
 public:
  explicit RotationalUpdate(const RotationOptions &o) : opts_(o) {}
  PetscErrorCode shapeDirection(NewtonContext &ctx, Direction &d, Vec X, Vec Y, Vec F, PetscBool *changed) override;

 private:
  RotationOptions opts_;
};

// 5. The element Hessians' eigenvalue filter; adaptive: clamp or abs per iteration by the trust-region ratio of the
// previous update (Chen et al. 2024).
// With -newton_exact_hessian, after a full-length update the next system is assembled unfiltered (the true Newton
// step, quadratic near the solution); an unfiltered system CG cannot solve as positive definite (negative curvature, a
// failed solve, or a direction that does not descend) is solved again with the filter before any strategy sees the
// direction (repairDirection), and the rest of the solve keeps the filter, as after an unfiltered step the line search
// or the safeguard had to shorten. Where the energy is not convex near the
// solutions (an inside-out recovery's tail) every attempt would fail: after a failed solve the next 1, 2, 4, ... 64
// solves (consecutive failures double it) keep the filter, and a solve whose unfiltered systems all were definite
// resets that back-off. With -newton_exact_start such a solve's successor (the next time or load step) assembles its
// first system unfiltered too: it starts where CG has just solved the true Hessian, and the filtered first update
// would leave an error at the compressed cells that costs one more update in most steps of a moving scene.
class HessianFilter final : public NewtonStep {
 public:
  explicit HessianFilter(const FilterOptions &o) : opts_(o) {}
  PetscErrorCode beginSolve(NewtonContext &ctx) override;
  PetscErrorCode shapeDirection(NewtonContext &ctx, Direction &d, Vec X, Vec Y, Vec F, PetscBool *changed) override;
  PetscErrorCode finishUpdate(NewtonContext &ctx, const Direction &d, Vec xNew, double lambda) override;
  // Before the strategies run: an unfiltered system that was not positive definite is solved again filtered.
  PetscErrorCode repairDirection(NewtonContext &ctx, Direction &d, Vec X, Vec Y, Vec F, PetscBool *changed);
  // What the filter carries from one solve to the next (the back-off), as the next solve would start with it: a
  // checkpoint keeps it, so a restarted run takes the same steps as an uninterrupted one.
  NewtonMemory memory() const;
  void restore(const NewtonMemory &m);
  // The filter of the solves that begin from now on (NewtonSolver::overrideFilter).
  void setMode(EigenFilterMode mode) { opts_.mode = mode; }
  // The next solve minimizes another energy than the last one (a shape stage's end): it starts filtered.
  void energyChanged() {
    if (lastSolveDefinite()) backoff_ = 0;
    usedExact_ = false;
  }

 private:
  PetscErrorCode giveUp(NewtonContext &ctx);
  PetscErrorCode chooseStart(NewtonContext &ctx, KSP ksp, Vec g, Vec Y);  // the filtered re-solve's start
  // The last solve assembled unfiltered systems and none of them was indefinite.
  bool lastSolveDefinite() const { return usedExact_ && !gaveUp_; }
  FilterOptions opts_;
  bool exactNow_ = false;  // this iteration's system is the unfiltered one
  bool gaveUp_ = false;    // an unfiltered system of this solve was indefinite: the filter for the rest of it
  bool usedExact_ = false; // this solve assembled an unfiltered system
  int backoff_ = 0;        // solves to keep the filter after the next failure / 2 (0: none failed lately)
  int skip_ = 0;           // solves left that keep the filter
  kernels::EigenFilter filtered_ = kernels::EigenFilter::Clamp;  // the filter an exact iteration falls back to
};

// 6. The alpha safeguard (paper Sec. 4.2): the direction is halved until the full step keeps every guarded element's
// alpha at or above -alpha_min, and so is any point a line search accepts.
class AlphaSafeguard final : public NewtonStep {
 public:
  explicit AlphaSafeguard(const SafeguardOptions &o) : opts_(o) {}
  bool appliesToFinalCorrection() const override { return true; }
  PetscErrorCode beginSolve(NewtonContext &) override {
    memoDisc_ = nullptr;  // a discretization gone since (the detached start's) cannot leave its address as a key
    return 0;
  }
  PetscErrorCode shapeDirection(NewtonContext &ctx, Direction &d, Vec X, Vec Y, Vec F, PetscBool *changed) override;
  PetscErrorCode checkPoint(NewtonContext &ctx, Direction &d, Vec X, Vec W, PetscBool *changed) override;
  // alpha check of a state against reference alphas (the state before the step): true unless a guarded cell ends
  // below alpha_min (or any alpha is NaN). A cell is guarded when its reference alpha is at or above the top of its
  // singular band (newton.hpp).
  PetscErrorCode acceptable(NewtonContext &ctx, Vec xGlobal, const std::vector<double> &reference, bool *ok);
  // The same rule on this rank's cells, given their guard values and singular bands' tops (no communication).
  bool rejects(const std::vector<double> &reference, const std::vector<double> &alpha,
               const std::vector<double> &bandTop) const;
  // Each local cell's guard value (alpha; fem::Discretization::cellGuard) at a global state, Dirichlet values filled.
  PetscErrorCode alphasAt(NewtonContext &ctx, Vec xGlobal, std::vector<double> *alpha);
  // The largest threshold rejects() compares guard values with, given the cells' singular bands' tops: guard values
  // need be exact only below it (cellGuard's exactBelow).
  double exactBelow(const std::vector<double> &bandTop) const;

 private:
  SafeguardOptions opts_;
  std::vector<double> alphaRef_, bandTop_;
  // The last state alphasAt evaluated (its local values, boundary values included, and the discretization) and its
  // alphas: an update checks the same state up to three times (the accepted point as the next direction's reference,
  // the full step before the line search, and the point the line search accepts, which is that full step when it
  // takes it), and each evaluation is a pass over every cell (the root only where 64 J does not clear the thresholds).
  // The values are exact below memoExactBelow_ only: a memo taken under other thresholds is not reused.
  const fem::Discretization *memoDisc_ = nullptr;  // null: memoAlpha_ belongs to no state
  LocalStateKey memoState_;
  std::vector<double> memoAlpha_;
  double memoExactBelow_ = 0.0;
};

}  // namespace aries::solver
