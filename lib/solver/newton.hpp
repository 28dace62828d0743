// Projected Newton on the total potential with PETSc SNES (newtonls), KSP CG + Jacobi by default.
//
//  * Model: the energy is the SNES objective (line searches work on it), its gradient the residual, the assembled
//    eigenvalue-filtered Hessian the Jacobian (DMSNES local callbacks; Dirichlet values filled by the boundary
//    callback). The filter is -psd_projection clamp|abs|adaptive|none (kernels/psd_projection.hpp); adaptive picks
//    clamp or abs per Newton iteration by the trust-region ratio of the previous update (Chen et al. 2024).
//  * Convergence is decided on the Newton direction BEFORE any line search (paper Sec. 6): a step is converged when
//    the inf-norm of the Newton step from a converged linear solve is at most -newton_tol * L (* dt for backward
//    Euler), L the rest bounding-box diagonal. That small step is applied as a final correction (no line search, the
//    safeguard still applies) and not counted as an update, so a state at rest converges with 0 updates (reason
//    converged_initial). Backward Euler with a PSD-filtered Hessian has H >= M / dt^2, which bounds the Newton step
//    by the residual alone (stepBound): below the tolerance the step is certified without a linear solve (reason
//    step_bound). A direction whose predicted energy decrease is below the energy's round-off and whose step is
//    within kRoundoffStepFactor x the tolerance is converged too (energy_roundoff, at any iteration; not applied):
//    no line search can measure progress there (convergence_rule.hpp). PETSc's
//    relative residual test is off by default (-snes_rtol 0): a residual small relative to a huge initial one (a
//    scrambled start) is not equilibrium. A direction from a loose linear solve (-newton_forcing, -snes_ksp_ew)
//    certifies only through a bound on its error or after a solve at -ksp_rtol.
//  * Subspace acceleration (-newton_subspace m): the update minimizes the true quadratic model (exact Hessian) over
//    span{Newton direction, last m updates}, a Newton-preconditioned nonlinear-CG / SESOP step. Filtering makes the
//    model of inverted and compressed elements stiffer than they are, so plain projected Newton converges linearly
//    with steps that are too short; the exact curvature in a small subspace restores the step length and direction.
//  * Rotational update (-newton_rotation K): a Newton step is linear in the positions, so it can only turn a part of
//    the body along the tangent of its rotation (stretching it); where the direction is locally a rotation (its spin,
//    the skew part of grad_x of the step, averaged per vertex) the vertex follows the circle by the same angle
//    instead, and up to K doublings of that angle are tried while the energy falls. Taken only where it lowers the
//    energy more than the plain direction and stays a descent direction. Unwinding a body twisted about its
//    supports (static solves from scrambled starts) otherwise takes dozens of short Newton steps.
//  * The alpha safeguard (paper Sec. 4.2) as line-search pre/post checks: no accepted step takes an element whose
//    alpha is at or above the top of its singular band to below -alpha_min; the step is halved until it holds. The
//    band is [0, mollifier eps) for elements evaluated with the mollifier (there the I4/I6 terms are the constant
//    proxy and nothing is singular) and [0, alpha_min) otherwise, so elements already inside it never block a step.
//  * The rigid-body modes of the rest shape are the Jacobian's near-nullspace (-near_nullspace rigid|none), for GAMG.
// Every default is a PETSc option and can be overridden (-snes_*, -ksp_*, -pc_*, -snes_linesearch_*).
#pragma once

#include "fem/discretization.hpp"
#include "solver/convergence_rule.hpp"

#include <petscsnes.h>

#include <string>
#include <vector>

namespace aries::solver {

// The six rigid-body modes (orthonormalized) of the positions in a global vector with `dofsPerVertex` per vertex.
PetscErrorCode rigidBodyModes(Vec positions, PetscInt dofsPerVertex, MatNullSpace *modes);


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
};

struct NewtonResult {
  PetscInt newtonIterations = 0;   // updates of the state (line searches that moved it)
  PetscInt linearSolves = 0;       // Newton systems solved (one per direction, including the converging one)
  PetscInt linearIterations = 0;   // Krylov iterations over all of them
  PetscInt linearAtLimit = 0;      // linear solves stopped by -ksp_max_it (their direction is not a Newton step)
  PetscInt safeguardHalvings = 0;
  SNESConvergedReason reason = SNES_CONVERGED_ITERATING;
  Convergence convergence = Convergence::None;
  PetscInt barrierFallbackCells = 0;  // cells evaluated with the mollifier in barrier mode (alpha ~ 0)
  PetscInt barrierActiveCells = 0;    // cells with an active aberration barrier (0 < alpha < eps) at the step start
  PetscReal residualNorm = 0.0;       // |gradient of the potential|_2 over the free dofs at the last iterate
  std::vector<IterationRecord> history;
  bool converged() const { return reason > 0; }
  NewtonResult &operator+=(const NewtonResult &o);  // sums the counters, keeps o's outcome, appends its history
};

enum class EigenFilterMode { Clamp, Abs, Adaptive, None };

class NewtonSolver {
 public:
  ~NewtonSolver();
  // Reads the Newton options (docs/options.md, "Time stepping and solver"); `dynamic` selects the backward Euler
  // defaults (dt-scaled tolerance, clamp filter, unlimited subspace step, inertia initial guess).
  // `base` and `prefix`: a solver for a phase of its own (the detached start, prefix "detached_"): its Newton options
  // and PETSc solver settings start from `base`'s (SNES tolerances, line search type, KSP type and tolerances, PC
  // type) and are overridden by the same options under the prefix (-detached_newton_tol, -detached_snes_max_it, ...).
  PetscErrorCode setup(fem::Discretization &disc, bool dynamic, double dt, const NewtonSolver *base = nullptr,
                       const char *prefix = nullptr);
  PetscErrorCode solve(Vec x, NewtonResult *result);  // x: initial guess in, solution out (global, free dofs)
  // The time step changed (-on_failure halve_dt): tolerance and step bound follow it.
  PetscErrorCode setTimeStep(double dt);

  // alpha check of a state against reference alphas (the state before the step): true unless a guarded cell ends
  // below alphaMin (or any alpha is NaN). A cell is guarded when its reference alpha is at or above the top of its
  // singular band (see the file comment).
  PetscErrorCode alphaAcceptable(Vec xGlobal, const std::vector<double> &reference, bool *ok);
  PetscErrorCode alphasAt(Vec xGlobal, std::vector<double> *alpha);
  // Total potential at a global state (Dirichlet values filled); `magnitude` as in Discretization::objective.
  PetscErrorCode energyAt(Vec xGlobal, PetscReal *value, PetscReal *magnitude);
  double alphaMin() const { return alphaMin_; }
  // A body without supports (the detached start): its energy is invariant under rigid motions, so the Newton
  // direction's rigid-motion share (which CG on the singular system leaves undetermined) is removed before the
  // convergence test and the line search.
  void setFloating(bool floating) { floating_ = floating; }
  double stepTolerance() const { return stepTol_; }
  SNES snes() const { return snes_; }
  PetscInt totalHalvings() const { return halvingsTotal_; }

 private:
  PetscErrorCode readOptions(bool dynamic, const NewtonSolver *base, const char *prefix);
  PetscErrorCode copySolverSettings(const NewtonSolver &base);
  PetscErrorCode attachNearNullSpace();
  PetscErrorCode configureMultigrid();
  PetscErrorCode stepBound(Vec g, PetscReal *bound);  // backward Euler bound on |H^-1 g|_inf
  PetscErrorCode inertiaGuess(Mat H);                 // initial guess of the linear solve
  PetscErrorCode gram(Vec X, const std::vector<Vec> &directions, std::vector<double> *G);
  PetscErrorCode certify(Vec X, Vec Y, Vec F, PetscInt iter, bool *converged);
  PetscErrorCode accelerate(Vec X, Vec Y, Vec F, PetscBool *changed);
  PetscErrorCode rotate(Vec X, Vec Y, Vec F, PetscBool *changed);  // the rotational update (-newton_rotation)
  PetscErrorCode removeRigidMotion(Vec X, Vec Y);
  PetscErrorCode safeguard(Vec X, Vec Y, PetscBool *changed);
  PetscErrorCode finishUpdate(Vec xNew);  // after an update: line-search length, adaptive filter, subspace limit
  void declareConverged(Convergence how);
  kernels::EigenFilter initialFilter() const;
  static PetscErrorCode objectiveCallback(SNES, Vec, PetscReal *, void *);
  static PetscErrorCode boundaryLocal(DM, Vec, void *);
  static PetscErrorCode functionLocal(DM, Vec, Vec, void *);
  static PetscErrorCode jacobianLocal(DM, Vec, Mat, Mat, void *);
  static PetscErrorCode preCheck(SNESLineSearch, Vec, Vec, PetscBool *, void *);
  static PetscErrorCode postCheck(SNESLineSearch, Vec, Vec, Vec, PetscBool *, PetscBool *, void *);
  static PetscErrorCode convergenceTest(SNES, PetscInt, PetscReal, PetscReal, PetscReal, SNESConvergedReason *,
                                        void *);
  static PetscErrorCode linearConvergence(KSP, PetscInt, PetscReal, KSPConvergedReason *, void *);

  fem::Discretization *disc_ = nullptr;
  SNES snes_ = nullptr;
  Mat J_ = nullptr;
  double postScale_ = 1.0;  // the share of the line search's length postCheck kept (the alpha safeguard)
  Vec work_ = nullptr, invMass_ = nullptr, prevX_ = nullptr, newtonDir_ = nullptr;
  std::vector<Vec> history_;  // previous updates of this solve, newest first
  bool dynamic_ = false;
  double dt_ = 0.0, minMass_ = 0.0;

  // Options.
  double newtonTol_ = 0.0, stepTol_ = 0.0;
  double alphaMin_ = 1e-6;
  EigenFilterMode filterMode_ = EigenFilterMode::Clamp;
  bool analyticEigensystem_ = true;  // -psd_eigensystem analytic|numeric
  double adaptiveTol_ = 0.01;
  PetscInt subspace_ = 1;
  double subspaceMax_ = 0.0;   // limit of the Newton direction's coefficient in a subspace step (0: none)
  bool floating_ = false;
  int nearNullspace_ = 0;       // -near_nullspace rigid|none
  PetscInt rotation_ = -1;      // rotational update: -1 off, else the number of angle doublings tried
  bool useInertiaGuess_ = true;
  double forcing_ = 0.0;
  PetscReal baseRtol_ = 1e-6;  // the linear solve's tolerance without forcing (certifying solves)
  void *defaultKspCtx_ = nullptr;

  // State of the solve in progress.
  NewtonResult cur_;
  IterationRecord pending_;            // the iteration whose line search is running
  bool havePending_ = false;
  PetscInt historyCount_ = 0;
  bool haveCurvature_ = false;         // adaptive filter: the true curvature of the update being taken is known
  double energyBefore_ = 0.0, slope_ = 0.0, curvatureFull_ = 0.0;
  bool halved_ = false;                // the safeguard shortened this iteration's direction
  bool lastFull_ = false;              // the previous update was a full, unshortened step
  double rnorm0_ = 0.0;                // reference of the linear solve's relative residual
  bool forcingStopped_ = false;        // the last linear solve stopped early (-newton_forcing)
  std::vector<double> alphaRef_, bandTop_;
  PetscInt halvingsTotal_ = 0;
  PetscLogStage assemblyStage_ = -1;
};

// Short name of a Newton outcome for stats and console ("newton_step", "converged_initial", "diverged_line_search").
std::string reasonName(const NewtonResult &r);
const char *filterModeName(EigenFilterMode m);

}  // namespace aries::solver
