// Projected Newton on the total potential with PETSc SNES (newtonls), KSP CG + Jacobi by default (CG + GAMG for a
// large static solve, CG + point-block Jacobi for a dynamic degenerate start with fibers: choosePreconditioner).
//
//  * Model: the energy is the SNES objective (line searches work on it), its gradient the residual, the assembled
//    eigenvalue-filtered Hessian the Jacobian (DMSNES local callbacks; Dirichlet values filled by the boundary
//    callback).
//  * A step that moves the supports starts with lifted updates (lifted_increment.cpp, -lift_increments): the
//    increment of the prescribed motion enters the linear solve, the interior moving with its supports, and the
//    safeguard and a merit test shorten the combined update; SNES then iterates with the supports fixed.
//  * The strategies that turn the Newton direction into an update are objects with their own options and state
//    (newton_steps.hpp), run in a fixed order in the line search's pre-check: rigid-motion removal (a floating body),
//    the convergence check, the subspace step, the rotational update, the adaptive filter's model, the alpha
//    safeguard; after the line search the safeguard checks the accepted point, and after each update the steps see
//    its length.
//  * Convergence is decided on the Newton direction BEFORE any line search (paper Sec. 6): a step is converged when
//    the inf-norm of the Newton step from a converged linear solve is at most -newton_tol * L (* dt for backward
//    Euler), L the rest bounding-box diagonal (the dynamic shape stage converges at its own, looser X L:
//    loosenStepTolerance). That small step is applied as a final correction (no line search, the safeguard still
//    applies; only where it lowers |g|) and not counted as an update, so a state at rest converges with 0 updates
//    (reason converged_initial). Backward Euler with a PSD-filtered Hessian has H >= M / dt^2, which bounds the
//    Newton step by the residual alone: below the tolerance the step is certified without a linear solve (reason
//    step_bound).
//    A direction whose predicted energy decrease is below the energy's round-off and whose step is within
//    kRoundoffStepFactor x the tolerance is converged too (energy_roundoff, at any iteration; applied like the final
//    correction): no line search can measure progress there (convergence_rule.hpp). A longer flat direction is an
//    update taken in full where it lowers |g| (a residual step), not through the energy line search. PETSc's relative residual test is off by default
//    (-snes_rtol 0): a residual small relative to a huge initial one (a scrambled start) is not equilibrium.
//  * The rigid-body modes of the rest shape are the Jacobian's near-nullspace (-near_nullspace rigid|none), for GAMG.
// Every default is a PETSc option and can be overridden (-snes_*, -ksp_*, -pc_*, -snes_linesearch_*).
#pragma once

#include "fem/discretization.hpp"
#include "solver/newton_options.hpp"
#include "solver/newton_steps.hpp"

#include <petscsnes.h>

#include <memory>
#include <string>
#include <vector>

namespace aries::solver {

// The six rigid-body modes (orthonormalized) of the positions in a global vector with `dofsPerVertex` per vertex.
PetscErrorCode rigidBodyModes(Vec positions, PetscInt dofsPerVertex, MatNullSpace *modes);
// The same modes restricted to the free dofs of a layout in which some vertices are held in some components only (no
// block structure), orthonormalized; `like` gives the global vector layout.
PetscErrorCode rigidBodyModesOfFreeDofs(const fem::Kinematics &kin, PetscInt dofsPerVertex, Vec like,
                                        MatNullSpace *modes);

class NewtonSolver {
 public:
  ~NewtonSolver();
  // `options` from readNewtonOptions; `dynamic` selects backward Euler (dt-scaled tolerance, step bound, inertia
  // guess). `base` and `prefix`: a solver for a phase of its own (the detached start, prefix "detached_"): its PETSc
  // solver settings start from `base`'s (SNES tolerances, line search type, KSP type and tolerances, PC type) and are
  // overridden by the same options under the prefix (-detached_snes_max_it, ...). `floating`: a body without
  // supports (the rigid-motion removal step).
  PetscErrorCode setup(fem::Discretization &disc, const NewtonOptions &options, bool dynamic, double dt,
                       const NewtonSolver *base = nullptr, const char *prefix = nullptr, bool floating = false);
  PetscErrorCode solve(Vec x, NewtonResult *result);  // x: initial guess in, solution out (global, free dofs)
  // A solve that also takes the load from the discretization's (fem::StepState::load) to `target` (-lift_increments,
  // lifted_increment.cpp): lifted updates carry the increment of the prescribed motion, the surface loads and the
  // keyframed fields into the linear solves until the load reaches the target (or the combined step converges), then
  // Newton continues at that load. The load it ends at is the discretization's (short of the target only when the
  // safeguard kept shortening the lifted updates: the rest is a load sub-step). *advanced false: no length of the first
  // lifted update was acceptable; nothing moved (the state, the load), the result counts its linear solve.
  PetscErrorCode solve(Vec x, double target, NewtonResult *result, bool *advanced);
  // The time step changed (-on_failure halve_dt): tolerance and step bound follow it.
  PetscErrorCode setTimeStep(double dt);
  // Converged at a Newton step of inf-norm `stepTol` where that is looser than -newton_tol's, until the next call (0:
  // -newton_tol's again). For a solve that only moves where another starts (the dynamic shape stage, shape_first.cpp).
  PetscErrorCode loosenStepTolerance(double stepTol);
  // The solves that begin from now on filter the element Hessians with `mode` (clamp or abs), until
  // restoreFilter(); not where the filter is off (-psd_projection none, a reference solve). For a run whose start
  // asks for another filter than -psd_projection's (-beuler_start_psd_projection, Simulation::advance); memory()
  // carries it, so a restarted run keeps it.
  void overrideFilter(EigenFilterMode mode);
  void restoreFilter();
  // The next solve minimizes another energy than the last one (after a shape stage, shape_first.cpp): its first system
  // is filtered, whatever -newton_exact_start would take from the last solve.
  void energyChanged();

  // The alpha safeguard's check of a state against reference alphas (AlphaSafeguard::acceptable).
  PetscErrorCode alphaAcceptable(Vec xGlobal, const std::vector<double> &reference, bool *ok);
  PetscErrorCode alphasAt(Vec xGlobal, std::vector<double> *alpha);
  // Total potential at a global state (Dirichlet values filled); `magnitude` as in Discretization::objective.
  PetscErrorCode energyAt(Vec xGlobal, PetscReal *value, PetscReal *magnitude);
  double alphaMin() const { return opts_.safeguard.alphaMin; }
  // -lift_increments auto with inertia: a step starts from its supports moved alone where the alpha safeguard accepts
  // that move, and is lifted only where it does not (lifted_increment.cpp says why).
  bool supportsAloneFirst() const;
  // The state the solver carries from one solve to the next (checkpointed with the run's state).
  NewtonMemory memory() const;
  void restore(const NewtonMemory &m);

 private:
  PetscErrorCode copySolverSettings(const NewtonSolver &base);
  PetscErrorCode attachNearNullSpace();
  PetscErrorCode configureMultigrid();
  // The preconditioner rule (-pc_type not given): GAMG for a large static solve, else Jacobi.
  PetscErrorCode choosePreconditioner(bool dynamic, bool matTypeGiven, bool aij, const char *prefix);
  PetscErrorCode solveCoarseSingularSystem(const char *prefix);
  PetscErrorCode chooseMatrixType(DM dm, const NewtonSolver *base, bool dynamic, const char *prefix, bool floating);
  PetscErrorCode avoidMultigridWhenFloating(PC pc, const char *prefix);
  PetscErrorCode finishUpdate(Vec xNew);  // after an update: its record and every step's finishUpdate
  // The lifted load increment (lifted_increment.cpp).
  PetscErrorCode setLoad(double load);
  PetscErrorCode gradientAt(Vec xLocal, Vec gLocal, Vec gGlobal);
  PetscErrorCode liftedDirection(Vec xLocal, Vec coupling, Vec b, Vec p, IterationRecord *rec, bool *solved);
  PetscErrorCode liftedLength(Vec x, Vec p, double s, double target, const std::vector<double> &alphaRef,
                              bool certifying, double *lambda);
  PetscErrorCode liftedUpdate(Vec x, double target, bool *advanced, bool *converged);
  PetscErrorCode liftIncrement(Vec x, double target, bool *advanced, bool *converged);
  PetscErrorCode finishResult(bool snesRan, NewtonResult *result);
  static PetscErrorCode objectiveCallback(SNES, Vec, PetscReal *, void *);
  static PetscErrorCode boundaryLocal(DM, Vec, void *);
  static PetscErrorCode functionLocal(DM, Vec, Vec, void *);
  static PetscErrorCode jacobianLocal(DM, Vec, Mat, Mat, void *);
  static PetscErrorCode preCheck(SNESLineSearch, Vec, Vec, PetscBool *, void *);
  PetscErrorCode stepIfResidualDrops(Vec X, Vec Y, Vec F, bool *applied);
  static PetscErrorCode postCheck(SNESLineSearch, Vec, Vec, Vec, PetscBool *, PetscBool *, void *);
  static PetscErrorCode convergenceTest(SNES, PetscInt, PetscReal, PetscReal, PetscReal, SNESConvergedReason *,
                                        void *);

  NewtonOptions opts_;
  NewtonContext ctx_;
  // The preconditioner rule's choices (choosePreconditioner; the detached start's solver inherits them, but GAMG as
  // Jacobi: avoidMultigridWhenFloating): GAMG for large static solves, point-block Jacobi for dynamic degenerate
  // starts with fibers.
  bool multigridByRule_ = false;
  bool pointBlockByRule_ = false;
  std::vector<std::unique_ptr<NewtonStep>> steps_;  // in the order they run
  ConvergenceCheck *check_ = nullptr;               // owned by steps_
  HessianFilter *filter_ = nullptr;                 // owned by steps_
  AlphaSafeguard *safeguard_ = nullptr;             // owned by steps_
  Direction pending_;        // the direction whose line search is running
  bool havePending_ = false;
  struct {
    Vec rhs = nullptr, step = nullptr, trial = nullptr;  // r_f + H_fd d, the lifted step p, a trial state
    Vec coupling = nullptr;                              // H_fd d
  } lift_;
  struct {
    Vec before = nullptr;  // the iterate before the update in progress
    KSP ksp = nullptr;     // the local systems' CG + Jacobi
  } local_;
  // After a concentrated update (local_solve.cpp): Newton on the vertices it moved; F and *fnorm follow x.
  PetscErrorCode localSolve(Vec x, Vec F, PetscReal *fnorm);
  PetscErrorCode localSet(Vec x, Vec mark, bool *found);
  PetscInt kspBefore_ = 0;   // the KSP's total iterations when the solve began
  int filterOverride_ = -1;       // overrideFilter's EigenFilterMode (-1: -psd_projection's)
  double stepTolLoosened_ = 0.0;  // loosenStepTolerance (0: -newton_tol's)
};

// Short name of a Newton outcome for stats and console ("newton_step", "converged_initial", "diverged_line_search").
std::string reasonName(const NewtonResult &r);

}  // namespace aries::solver
