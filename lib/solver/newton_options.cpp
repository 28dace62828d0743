#include "solver/newton_options.hpp"

#include "core/options.hpp"
#include "solver/solver_options.hpp"

namespace aries::solver {

// Defaults chosen by measurement (docs/results.md): backward Euler clamps (inertia keeps the system definite, and
// clamping leaves the inverted elements' soft modes soft), static solves take absolute values (no inertia: clamped
// Hessians of a scrambled body are near-singular); the subspace step is unlimited with inertia and limited to twice
// the Newton step, after full steps only, without it (a static solve from a scramble can otherwise jump into another
// basin, e.g. a folded body); a solve after one whose unfiltered systems were all definite starts unfiltered
// (-newton_exact_start: as many updates or fewer and fewer linear solves on the moving scenes measured, test cylinder
// and Fig. 6 / Fig. 13 scenes). An option only read where it applies (-psd_adaptive_tol with the adaptive filter,
// -newton_subspace_max and -newton_extrapolate with a subspace step, -newton_exact_start with -newton_exact_hessian,
// -newton_inertia_guess for backward Euler) is reported unused elsewhere.
PetscErrorCode readNewtonOptions(bool dynamic, const NewtonOptions *base, const char *prefix, NewtonOptions *o) {
  const core::ReadContext at{prefix, dynamic ? "beuler" : "static", base != nullptr};
  PetscFunctionBeginUser;
  *o = base ? *base : NewtonOptions{};
  PetscCall(core::get(opt::newtonTol, &o->convergence.tol, nullptr, at));
  PetscCall(core::get(opt::alphaMin, &o->safeguard.alphaMin, nullptr, at));
  PetscCall(core::getChoice(opt::psdProjection, &o->filter.mode, nullptr, at));
  int eigensystem = o->filter.analyticEigensystem ? 0 : 1;  // analytic|numeric
  PetscCall(core::getChoice(opt::psdEigensystem, &eigensystem, nullptr, at));
  o->filter.analyticEigensystem = eigensystem == 0;
  int scope = o->filter.wholeElement ? 1 : 0;  // point|element
  PetscCall(core::getChoice(opt::psdScope, &scope, nullptr, at));
  o->filter.wholeElement = scope == 1;
  if (o->filter.mode == EigenFilterMode::Adaptive)
    PetscCall(core::get(opt::psdAdaptiveTol, &o->filter.adaptiveTol, nullptr, at));
  PetscBool exact = o->filter.exactNearSolution ? PETSC_TRUE : PETSC_FALSE;
  if (o->filter.mode != EigenFilterMode::None) PetscCall(core::get(opt::newtonExactHessian, &exact, nullptr, at));
  o->filter.exactNearSolution = exact && o->filter.mode != EigenFilterMode::None;
  if (o->filter.exactNearSolution) {
    PetscBool start = o->filter.exactStart ? PETSC_TRUE : PETSC_FALSE;
    PetscCall(core::get(opt::newtonExactStart, &start, nullptr, at));
    o->filter.exactStart = start;
  }
  PetscCall(core::get(opt::newtonSubspace, &o->subspace.size, nullptr, at));
  if (o->subspace.size > 0) {
    PetscCall(core::get(opt::newtonSubspaceMax, &o->subspace.maxCoefficient, nullptr, at));
    if (o->subspace.maxCoefficient > 0.0 && o->subspace.maxCoefficient < 1.0)
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -%snewton_subspace_max must be 0 (no limit) or >= 1 (got %g)",
              prefix ? prefix : "", o->subspace.maxCoefficient);
    PetscCall(core::get(opt::newtonExtrapolate, &o->subspace.extrapolate, nullptr, at));
  }
  PetscCall(core::get(opt::newtonRotation, &o->rotation.doublings, nullptr, at));
  PetscCall(core::get(opt::newtonLocalSolve, &o->local.maxIterations, nullptr, at));
  PetscCall(core::get(opt::newtonForcing, &o->convergence.forcing, nullptr, at));
  PetscCall(core::getChoice(opt::liftIncrements, &o->lift, nullptr, at));
  PetscBool guess = PETSC_FALSE;
  if (dynamic) PetscCall(core::get(opt::newtonInertiaGuess, &guess, nullptr, at));
  o->inertiaGuess = guess;
  int nullspace = o->rigidNearNullspace ? 0 : 1;  // rigid|none
  PetscCall(core::getChoice(opt::nearNullspace, &nullspace, nullptr, at));
  o->rigidNearNullspace = nullspace == 0;
  // the preconditioner rule is the run's: a phase's solver inherits its choice (the detached start's, a floating
  // body, gets Jacobi for GAMG: NewtonSolver::avoidMultigridWhenFloating)
  if (!base) {
    PetscCall(core::get(opt::multigridMinDofs, &o->multigridMinDofs, nullptr, at));
    PetscCall(core::get(opt::multigridReuseGrowth, &o->multigridReuseGrowth, nullptr, at));
  }
  PetscFunctionReturn(0);
}

}  // namespace aries::solver
