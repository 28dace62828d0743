// 5. HessianFilter (newton_steps.hpp, -psd_projection clamp|abs|adaptive|none, -psd_eigensystem, -psd_scope,
// -psd_adaptive_tol, -newton_exact_hessian): the eigenvalue filter of the element Hessians (kernels/psd_projection.hpp), per quadrature point
// or per whole element. Adaptive picks clamp or abs per Newton
// iteration by the trust-region ratio of the previous update (Chen et al. 2024): rho = actual / predicted decrease with
// the true quadratic model of the update taken; clamp where the model is trustworthy (|rho - 1| < -psd_adaptive_tol:
// fast local convergence), abs otherwise (robust far from equilibrium). The first iteration of a solve has no model
// to judge: abs.
#include "solver/local_vec.hpp"
#include "solver/newton_steps.hpp"

#include <algorithm>
#include <cmath>

namespace aries::solver {

namespace {
constexpr int kMaxBackoff = 64;  // solves that keep the filter after consecutive failed unfiltered systems, at most
}  // namespace

PetscErrorCode HessianFilter::beginSolve(NewtonContext &ctx) {
  kernels::EigenFilter initial = kernels::EigenFilter::Clamp;
  switch (opts_.mode) {
    case EigenFilterMode::Clamp: initial = kernels::EigenFilter::Clamp; break;
    case EigenFilterMode::None: initial = kernels::EigenFilter::None; break;
    case EigenFilterMode::Abs:
    case EigenFilterMode::Adaptive: initial = kernels::EigenFilter::Abs; break;
  }
  ctx.disc->setEigenFilter(initial);
  ctx.disc->setAnalyticEigensystem(opts_.analyticEigensystem);
  ctx.disc->setWholeElementFilter(opts_.wholeElement);
  const bool lastDefinite = lastSolveDefinite();
  if (lastDefinite) backoff_ = 0;
  exactNow_ = usedExact_ = false;
  gaveUp_ = skip_ > 0;  // backing off: this solve keeps the filter
  if (skip_ > 0) --skip_;
  filtered_ = initial;
  if (opts_.exactStart && !gaveUp_ && lastDefinite) {
    exactNow_ = usedExact_ = true;  // -newton_exact_start: as after a full-length update
    ctx.disc->setEigenFilter(kernels::EigenFilter::None);
  }
  return 0;
}

NewtonMemory HessianFilter::memory() const {
  const bool lastDefinite = lastSolveDefinite();
  NewtonMemory m{lastDefinite ? 0 : backoff_, skip_};
  m.filterExactStart = lastDefinite ? 1 : 0;
  return m;
}

void HessianFilter::restore(const NewtonMemory &m) {
  backoff_ = m.filterBackoff;
  skip_ = m.filterSkip;
  usedExact_ = m.filterExactStart != 0;  // the last solve's unfiltered systems were all definite (its back-off is 0)
  gaveUp_ = false;
}

// The unfiltered systems failed this solve: the filter for the rest of it and, doubling with each consecutive
// failure, for the next solves.
PetscErrorCode HessianFilter::giveUp(NewtonContext &ctx) {
  exactNow_ = false;
  gaveUp_ = true;
  backoff_ = backoff_ == 0 ? 1 : std::min(2 * backoff_, kMaxBackoff);
  skip_ = backoff_;
  ctx.disc->setEigenFilter(filtered_);
  return 0;
}

PetscErrorCode HessianFilter::repairDirection(NewtonContext &ctx, Direction &d, Vec X, Vec Y, Vec F,
                                              PetscBool *changed) {
  KSP ksp;
  KSPConvergedReason reason;
  PetscScalar slope;
  PetscInt its;
  PetscFunctionBeginUser;
  if (!exactNow_) PetscFunctionReturn(0);
  PetscCall(SNESGetKSP(ctx.snes, &ksp));
  PetscCall(KSPGetConvergedReason(ksp, &reason));
  PetscCall(VecDot(F, Y, &slope));
  if (linearSolveSolved(reason) && slope > 0.0) PetscFunctionReturn(0);
  PetscCall(giveUp(ctx));
  IterationRecord failed = d.record;  // the unfiltered attempt keeps its row (one row per linear solve), not applied
  failed.lambda = 0.0;
  PetscCall(VecNorm(Y, NORM_INFINITY, &failed.stepInf));
  ctx.result.history.push_back(failed);
  {
    LocalVec xl(ctx.disc->dm());
    PetscCall(xl.fromGlobal(X, ctx.disc));
    PetscCall(ctx.beginAssembly());
    PetscCall(ctx.disc->hessian(xl.get(), ctx.J));
    PetscCall(ctx.endAssembly());
  }
  PetscCall(KSPSetOperators(ksp, ctx.J, ctx.J));
  PetscCall(chooseStart(ctx, ksp, F, Y));
  PetscCall(ctx.solveWithNewPreconditioner(ksp, F, Y));  // a new matrix: the filtered one
  PetscCall(KSPGetIterationNumber(ksp, &its));
  d.record.linearIterations = its;
  d.record.preconditionerBuilt = true;
  d.record.filter = filterTag(filtered_);
  *changed = PETSC_TRUE;
  PetscFunctionReturn(0);
}

// The filtered re-solve's start: of the failed unfiltered direction Y (most of the Newton step where CG met negative
// curvature late; any length where the unfiltered system was near singular, and a start that far off wrecks the
// filtered solve), the inertia-only step (-newton_inertia_guess) and zero, the one with the least value of the
// filtered model q(p) = p^T H p / 2 - g^T p, which CG minimizes: the start nearest its solution in the H-norm.
PetscErrorCode HessianFilter::chooseStart(NewtonContext &ctx, KSP ksp, Vec g, Vec Y) {
  PetscScalar gY, yHy, gP, pHp;
  PetscFunctionBeginUser;
  PetscCall(MatMult(ctx.J, Y, ctx.work));
  PetscCall(VecDot(Y, ctx.work, &yHy));
  PetscCall(VecDot(g, Y, &gY));
  const double qFailed = 0.5 * yHy - gY;
  double qInertia = 0.0;  // zero's
  Vec p = ctx.trialX;     // free here: no trial point is pending before the line search
  if (ctx.inertiaGuess) {
    PetscCall(ctx.startFromInertia(ctx.J, g, p));
    PetscCall(MatMult(ctx.J, p, ctx.work));
    PetscCall(VecDot(p, ctx.work, &pHp));
    PetscCall(VecDot(g, p, &gP));
    qInertia = 0.5 * pHp - gP;  // 0 where it was not usable (p = 0)
  }
  const bool keepFailed = qFailed < 0.0 && qFailed <= qInertia;  // false for NaN
  const bool inertia = !keepFailed && qInertia < 0.0;
  if (inertia) PetscCall(VecCopy(p, Y));
  if (!keepFailed && !inertia) PetscCall(VecSet(Y, 0.0));
  PetscCall(KSPSetInitialGuessNonzero(ksp, keepFailed || inertia ? PETSC_TRUE : PETSC_FALSE));
  PetscFunctionReturn(0);
}

// The adaptive filter judges the update by its curvature: the subspace step's model knows it, else one product.
PetscErrorCode HessianFilter::shapeDirection(NewtonContext &ctx, Direction &d, Vec X, Vec Y, Vec, PetscBool *) {
  PetscFunctionBeginUser;
  if (opts_.mode != EigenFilterMode::Adaptive || d.haveCurvature) PetscFunctionReturn(0);
  std::vector<double> G;
  PetscCall(ctx.gram(X, {Y}, &G));
  d.curvature = G[0];
  d.haveCurvature = true;
  PetscFunctionReturn(0);
}

// The adaptive filter's choice by the update's model fit; then the exact Hessian for the next system after a
// full-length update (-newton_exact_hessian), the filter after a shortened one (the iterate is not yet where the
// quadratic model holds).
PetscErrorCode HessianFilter::finishUpdate(NewtonContext &ctx, const Direction &d, Vec xNew, double lambda) {
  PetscFunctionBeginUser;
  if (opts_.mode == EigenFilterMode::Adaptive && d.haveCurvature) {
    PetscReal energy;
    PetscCall(ctx.energyAt(xNew, &energy, nullptr));
    const double predicted = lambda * d.slope - 0.5 * lambda * lambda * d.curvature;
    const double rho = predicted != 0.0 ? (d.energyBefore - energy) / predicted : 0.0;
    filtered_ = std::abs(rho - 1.0) < opts_.adaptiveTol ? kernels::EigenFilter::Clamp : kernels::EigenFilter::Abs;
    ctx.disc->setEigenFilter(filtered_);
  }
  if (!opts_.exactNearSolution || gaveUp_) PetscFunctionReturn(0);
  const bool full = lambda == 1.0 && !d.halved;
  if (exactNow_ && !full) {  // the true model's step had to be shortened: not where it holds
    PetscCall(giveUp(ctx));
    PetscFunctionReturn(0);
  }
  exactNow_ = full;
  usedExact_ = usedExact_ || exactNow_;
  ctx.disc->setEigenFilter(exactNow_ ? kernels::EigenFilter::None : filtered_);
  PetscFunctionReturn(0);
}

}  // namespace aries::solver
