// 2. ConvergenceCheck (newton_steps.hpp, -newton_tol, -newton_forcing): convergence is decided on the Newton direction
// BEFORE any line search (paper Sec. 6). A step is converged when the inf-norm of the Newton step from a converged
// linear solve is at most the step tolerance; a direction whose predicted energy decrease is below the energy's
// round-off and whose step is within kRoundoffStepFactor x the tolerance is converged too (convergence_rule.hpp).
// Backward Euler with a PSD-filtered Hessian has H >= M / dt^2, which bounds the Newton step by the residual alone:
// below the tolerance an iterate is certified without a linear solve (testIterate). A direction from a loose linear
// solve (-newton_forcing, -snes_ksp_ew) certifies only through a bound on its error or after a solve at -ksp_rtol.
#include "solver/newton_steps.hpp"

namespace aries::solver {

namespace {
// A CG iterate this many times the step tolerance is a step that cannot be the last: its solve may stop early
// (-newton_forcing).
constexpr double kForcingMargin = 2.0;
// Checking the iterate costs a reduction: look every few CG iterations.
constexpr PetscInt kForcingCheckEvery = 5;

}  // namespace

ConvergenceCheck::~ConvergenceCheck() {
  if (defaultKspCtx_) KSPConvergedDefaultDestroy(defaultKspCtx_);
}

PetscErrorCode ConvergenceCheck::setup(NewtonContext &ctx) {
  KSP ksp;
  PetscFunctionBeginUser;
  ctx_ = &ctx;
  PetscCall(SNESGetKSP(ctx.snes, &ksp));
  PetscCall(KSPGetTolerances(ksp, &baseRtol_, nullptr, nullptr, nullptr));
  PetscCall(KSPConvergedDefaultCreate(&defaultKspCtx_));
  PetscCall(KSPSetConvergenceTest(ksp, linearTest, this, nullptr));
  PetscFunctionReturn(0);
}

// Is the state converged on the Newton direction Y (g . Y >= 0 descends along -Y)? A loose linear solve underestimates
// the Newton step (CG iterates grow in norm from a zero start), so a small loose step certifies only with a bound on
// its error (backward Euler: the step bound of the linear residual) or after a solve at the base tolerance.
PetscErrorCode ConvergenceCheck::shapeDirection(NewtonContext &ctx, Direction &d, Vec X, Vec Y, Vec F,
                                                PetscBool *) {
  KSP ksp;
  KSPConvergedReason linearReason;
  PetscReal stepInf, energy, magnitude, rtol;
  PetscScalar slope;
  PetscFunctionBeginUser;
  PetscCall(SNESGetKSP(ctx.snes, &ksp));
  PetscCall(KSPGetConvergedReason(ksp, &linearReason));
  PetscCall(VecNorm(Y, NORM_INFINITY, &stepInf));
  PetscCall(VecDot(F, Y, &slope));
  PetscCall(ctx.energyAt(X, &energy, &magnitude));
  d.record.energy = energy;
  d.record.stepInf = stepInf;
  d.energyBefore = energy;
  d.slope = slope;
  // A predicted decrease below the energy's round-off cannot be measured by any line search.
  DirectionMeasures m;
  m.linearConverged = linearSolveSolved(linearReason);
  m.iteration = static_cast<int>(d.record.iteration);
  m.stepInf = stepInf;
  m.stepTol = ctx.stepTol;
  m.slope = slope;
  m.roundoff = kRoundoffSafety * kernels::kEps * magnitude;
  d.roundoff = m.roundoff;
  Convergence how = classifyDirection(m);
  PetscCall(KSPGetTolerances(ksp, &rtol, nullptr, nullptr, nullptr));
  const bool loose = rtol > baseRtol_ || forcingStopped_;
  const bool small = how == Convergence::Initial || how == Convergence::NewtonStep;
  if (how != Convergence::None && loose) {
    bool bounded = false;
    if (small && ctx.dynamic) {
      PetscReal errorBound;
      PetscCall(MatMult(ctx.J, Y, ctx.work));
      PetscCall(VecAYPX(ctx.work, -1.0, F));  // the linear residual r = g - H p
      PetscCall(ctx.stepBound(ctx.work, &errorBound));
      bounded = stepInf + errorBound <= ctx.stepTol;
    }
    if (!bounded) {  // solve again at the base tolerance, from the loose solution
      PetscBool ew, guess;
      PetscCall(SNESKSPGetUseEW(ctx.snes, &ew));
      PetscCall(KSPGetInitialGuessNonzero(ksp, &guess));
      PetscCall(SNESKSPSetUseEW(ctx.snes, PETSC_FALSE));
      PetscCall(KSPSetTolerances(ksp, baseRtol_, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT));
      PetscCall(KSPSetInitialGuessNonzero(ksp, PETSC_TRUE));
      forcingOn_ = false;
      PetscCall(KSPSolve(ksp, F, Y));
      forcingOn_ = true;
      PetscCall(KSPSetInitialGuessNonzero(ksp, guess));
      PetscCall(SNESKSPSetUseEW(ctx.snes, ew));
      PetscCall(KSPGetConvergedReason(ksp, &linearReason));
      ctx.countLinearSolve(linearReason);
      PetscCall(VecNorm(Y, NORM_INFINITY, &stepInf));
      PetscCall(VecDot(F, Y, &slope));
      d.record.stepInf = stepInf;
      d.slope = slope;
      m.linearConverged = linearSolveSolved(linearReason);
      m.stepInf = stepInf;
      m.slope = slope;
      how = classifyDirection(m);
    }
  }
  if (how == Convergence::None) PetscFunctionReturn(0);
  ctx.declareConverged(how);
  // The converged direction is applied as a final correction (an exact solve's step, taken in full where it lowers
  // the gradient's norm; the safeguard still shapes it): NewtonSolver::stepIfResidualDrops. Not through the energy
  // line search: a step this short changes the energy by about its round-off, so the line search would accept or
  // reject it by chance (and differently on different rank counts).
  d.finalCorrection = true;
  PetscFunctionReturn(0);
}

// Backward Euler's step bound at the iterate (a converged state needs no linear solve).
PetscErrorCode ConvergenceCheck::testIterate(NewtonContext &ctx, PetscInt it, PetscReal fnorm,
                                             SNESConvergedReason *reason) {
  PetscFunctionBeginUser;
  if (*reason != SNES_CONVERGED_ITERATING && *reason != SNES_DIVERGED_MAX_IT) PetscFunctionReturn(0);
  Vec g;
  PetscReal bound;
  PetscCall(SNESGetFunction(ctx.snes, &g, nullptr, nullptr));
  PetscCall(ctx.stepBound(g, &bound));
  if (!(bound <= ctx.stepTol)) PetscFunctionReturn(0);
  ctx.result.convergence = it + ctx.iterationOffset == 0 ? Convergence::Initial : Convergence::StepBound;
  *reason = SNES_CONVERGED_SNORM_RELATIVE;
  IterationRecord rec;
  Vec x;
  rec.iteration = it + ctx.iterationOffset;
  rec.load = ctx.disc->load();
  rec.residual = fnorm;
  rec.stepInf = bound;  // a bound, not the step
  PetscCall(SNESGetSolution(ctx.snes, &x));
  PetscCall(ctx.energyAt(x, &rec.energy, nullptr));
  ctx.result.history.push_back(rec);
  PetscFunctionReturn(0);
}

// Inexact Newton with a step-aware stop (-newton_forcing eta): CG stops once its relative residual is below eta if
// its iterate already shows a Newton step well above the convergence tolerance (this cannot be the last direction);
// a direction that could certify convergence is always solved to -ksp_rtol. A solve with a kept multigrid hierarchy
// stops at its iteration limit (preconditioner_reuse.hpp) and is solved again with a new one.
PetscErrorCode ConvergenceCheck::linearTest(KSP ksp, PetscInt it, PetscReal rnorm, KSPConvergedReason *reason,
                                            void *ctx) {
  auto *self = static_cast<ConvergenceCheck *>(ctx);
  Vec work = self->ctx_->work;
  PetscFunctionBeginUser;
  PetscCall(KSPConvergedDefault(ksp, it, rnorm, reason, self->defaultKspCtx_));
  const long limit = self->ctx_->preconditioner.iterationLimit();  // a kept multigrid hierarchy gone stale
  if (*reason == KSP_CONVERGED_ITERATING && limit >= 0 && it >= limit) {
    *reason = KSP_DIVERGED_PC_FAILED;
    PetscFunctionReturn(0);
  }
  if (it == 0) {  // the reference of the relative test: |B b| (the preconditioned right-hand side), as KSP's own
    PetscBool guess;
    self->forcingStopped_ = false;
    self->rnorm0_ = rnorm;
    PetscCall(KSPGetInitialGuessNonzero(ksp, &guess));
    if (guess) {
      Vec b;
      PC pc;
      PetscCall(KSPGetRhs(ksp, &b));
      PetscCall(KSPGetPC(ksp, &pc));
      PetscCall(PCApply(pc, b, work));
      PetscCall(VecNorm(work, NORM_2, &self->rnorm0_));
    }
  }
  const double forcing = self->forcingOn_ ? self->opts_.forcing : 0.0;
  if (*reason != KSP_CONVERGED_ITERATING || !(forcing > 0.0) || it == 0 || it % kForcingCheckEvery)
    PetscFunctionReturn(0);
  if (!(rnorm <= forcing * self->rnorm0_)) PetscFunctionReturn(0);
  Vec x;
  PetscReal xinf;
  PetscCall(KSPBuildSolution(ksp, nullptr, &x));
  PetscCall(VecNorm(x, NORM_INFINITY, &xinf));
  if (xinf > kForcingMargin * self->ctx_->stepTol) {
    *reason = KSP_CONVERGED_RTOL;
    self->forcingStopped_ = true;
  }
  PetscFunctionReturn(0);
}

}  // namespace aries::solver
