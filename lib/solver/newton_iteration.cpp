// One Newton iteration of NewtonSolver (newton.hpp): the model callbacks (energy, gradient, filtered Hessian), the
// shared services of the strategies (NewtonContext), and the hooks that run the strategies (newton_steps.hpp) before
// and after each line search. Setup and the solve are in newton.cpp.
#include "solver/newton.hpp"
#include "solver/local_vec.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

namespace aries::solver {

namespace {
// A direction whose predicted energy change g . p is at most this many times the energy's round-off is flat: the
// round-off estimate (ConvergenceCheck: 1e3 eps x the sum of the terms' magnitudes) is conservative, and a line search
// needs a decrease well above the actual noise to tell it from zero.
constexpr double kFlatDirectionFactor = 1e3;
}  // namespace

// ---- the shared services -----------------------------------------------------------------------------------------

PetscErrorCode NewtonContext::beginAssembly() {
  PetscFunctionBeginUser;
  PetscCall(PetscLogStagePush(assemblyStage));
  assemblyStart = MPI_Wtime();
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonContext::endAssembly() {
  PetscFunctionBeginUser;
  result.assemblySeconds += MPI_Wtime() - assemblyStart;
  PetscCall(PetscLogStagePop());
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonContext::energyAt(Vec x, PetscReal *value, PetscReal *magnitude) {
  LocalVec xl(disc->dm());
  PetscFunctionBeginUser;
  PetscCall(beginAssembly());
  PetscCall(xl.fromGlobal(x, disc));
  if (!energyMemo.on) {
    PetscCall(disc->objective(xl.get(), value, magnitude));
    PetscCall(endAssembly());
    PetscFunctionReturn(0);
  }
  bool sameState = false;
  PetscCall(energyMemo.state.matches(xl.get(), &sameState));
  int same = energyMemo.valid && sameState;
  // The potential is a sum over ranks: every rank evaluates, or none.
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &same, 1, MPI_INT, MPI_MIN, PetscObjectComm((PetscObject)x)));
  if (!same) {
    energyMemo.valid = false;
    PetscCall(disc->objective(xl.get(), &energyMemo.value, &energyMemo.magnitude));
    energyMemo.valid = true;
  }
  *value = energyMemo.value;
  if (magnitude) *magnitude = energyMemo.magnitude;
  PetscCall(endAssembly());
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonContext::gram(Vec X, const std::vector<Vec> &directions, std::vector<double> *G) {
  const DM dm = disc->dm();
  LocalVec xl(dm);
  std::vector<std::unique_ptr<LocalVec>> dl;
  std::vector<Vec> d(directions.size());
  PetscFunctionBeginUser;
  PetscCall(xl.fromGlobal(X, disc));
  for (size_t k = 0; k < directions.size(); ++k) {
    dl.push_back(std::make_unique<LocalVec>(dm));
    PetscCall(dl[k]->fromGlobal(directions[k], nullptr));
    d[k] = dl[k]->get();
  }
  PetscCall(beginAssembly());
  PetscCall(disc->curvatureGram(xl.get(), d, G));
  PetscCall(endAssembly());
  PetscFunctionReturn(0);
}

// Backward Euler: H = M / dt^2 + K with K PSD (filtered), so with D = M / dt^2, p = H^-1 g satisfies
// p^T D p <= p^T H p = g^T H^-1 g <= g^T D^-1 g, hence |p_i| <= sqrt(g^T D^-1 g / D_ii) for every dof i:
// |p|_inf <= sqrt(g^T M^-1 g) dt^2 / sqrt(min_i m_i). Infinite where no such bound holds.
PetscErrorCode NewtonContext::stepBound(Vec g, PetscReal *bound) {
  PetscScalar gMg;
  PetscFunctionBeginUser;
  *bound = PETSC_INFINITY;
  if (!dynamic || !psdHessian || !(minMass > 0.0)) PetscFunctionReturn(0);
  PetscCall(VecPointwiseMult(work, g, invMass));
  PetscCall(VecDot(work, g, &gMg));
  *bound = std::sqrt(std::max(0.0, (double)gMg)) * dt * dt / std::sqrt(minMass);
  PetscFunctionReturn(0);
}

// Backward Euler: the linear solve H p = g starts from the inertia-only step scaled optimally in the H-norm,
// p0 = a M^-1 g with a = (g^T M^-1 g) / ((M^-1 g)^T H M^-1 g): never worse than a zero start in the H-norm, and exact
// for a rigid translation (free fall), where CG then has nothing left to do. Where H does not make it usable (not
// positive along it) the solve starts from zero.
PetscErrorCode NewtonContext::startFromInertia(Mat H, Vec g, Vec p) {
  KSP ksp;
  PetscScalar gv, vHv;
  PetscFunctionBeginUser;
  PetscCall(SNESGetKSP(snes, &ksp));
  PetscCall(VecPointwiseMult(p, g, invMass));
  PetscCall(MatMult(H, p, work));
  PetscCall(VecDot(g, p, &gv));
  PetscCall(VecDot(p, work, &vHv));
  const bool usable = vHv > 0.0 && gv > 0.0;
  if (usable)
    PetscCall(VecScale(p, gv / vHv));
  else
    PetscCall(VecSet(p, 0.0));
  PetscCall(KSPSetInitialGuessNonzero(ksp, usable ? PETSC_TRUE : PETSC_FALSE));
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonContext::finishSystem(KSP ksp, Vec b, Vec x) {
  KSPConvergedReason reason;
  PetscInt its;
  PetscFunctionBeginUser;
  PetscCall(KSPGetConvergedReason(ksp, &reason));
  PetscCall(KSPGetIterationNumber(ksp, &its));
  const bool kept = preconditioner.enabled() && !preconditioner.built();
  if (kept && !linearSolveSolved(reason) && reason != KSP_DIVERGED_INDEFINITE_MAT) {
    PetscBool guess;
    PetscCall(KSPGetInitialGuessNonzero(ksp, &guess));
    PetscCall(KSPSetInitialGuessNonzero(ksp, PETSC_FALSE));
    PetscCall(solveWithNewPreconditioner(ksp, b, x));
    PetscCall(KSPSetInitialGuessNonzero(ksp, guess));
  } else {
    preconditioner.endSystem(its, linearSolveSolved(reason));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonContext::solveWithNewPreconditioner(KSP ksp, Vec b, Vec x) {
  KSPConvergedReason reason;
  PetscInt its;
  PetscFunctionBeginUser;
  PetscCall(KSPSetReusePreconditioner(ksp, PETSC_FALSE));
  preconditioner.beginSystem(true);
  PetscCall(KSPSolve(ksp, b, x));
  PetscCall(KSPGetConvergedReason(ksp, &reason));
  PetscCall(KSPGetIterationNumber(ksp, &its));
  countLinearSolve(reason);
  preconditioner.endSystem(its, linearSolveSolved(reason));
  PetscFunctionReturn(0);
}

void NewtonContext::countLinearSolve(KSPConvergedReason reason) {
  ++result.linearSolves;
  if (reason == KSP_DIVERGED_ITS) ++result.linearAtLimit;
}

void NewtonContext::declareConverged(Convergence how) {
  result.convergence = how;
  SNESSetConvergedReason(snes, SNES_CONVERGED_SNORM_RELATIVE);
}

// ---- callbacks of the model -------------------------------------------------------------------------------------

PetscErrorCode NewtonSolver::boundaryLocal(DM, Vec xLocal, void *ctx) {
  PetscFunctionBeginUser;
  PetscCall(static_cast<NewtonSolver *>(ctx)->ctx_.disc->fillBoundary(xLocal));
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonSolver::functionLocal(DM, Vec xLocal, Vec gLocal, void *ctx) {
  auto *self = static_cast<NewtonSolver *>(ctx);
  PetscFunctionBeginUser;
  PetscCall(self->ctx_.beginAssembly());
  PetscCall(self->ctx_.disc->gradient(xLocal, gLocal));
  PetscCall(self->ctx_.endAssembly());
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonSolver::jacobianLocal(DM, Vec xLocal, Mat, Mat P, void *ctx) {
  auto *self = static_cast<NewtonSolver *>(ctx);
  PetscFunctionBeginUser;
  PetscCall(self->ctx_.beginAssembly());
  PetscCall(self->ctx_.disc->hessian(xLocal, P));
  PetscCall(self->ctx_.endAssembly());
  // SNESComputeJacobian reads the lag after this callback: -1 keeps the preconditioner, 1 builds it for this system
  PreconditionerReuse &pc = self->ctx_.preconditioner;
  if (pc.enabled()) PetscCall(SNESSetLagPreconditioner(self->ctx_.snes, pc.beginSystem() ? 1 : -1));
  if (self->ctx_.inertiaGuess) {
    Vec g, p;
    PetscCall(SNESGetFunction(self->ctx_.snes, &g, nullptr, nullptr));
    PetscCall(SNESGetSolutionUpdate(self->ctx_.snes, &p));
    PetscCall(self->ctx_.startFromInertia(P, g, p));
  }
  PetscFunctionReturn(0);
}

NewtonMemory NewtonSolver::memory() const {
  NewtonMemory m = filter_ ? filter_->memory() : NewtonMemory{};
  m.filterOverride = filterOverride_;
  return m;
}

void NewtonSolver::restore(const NewtonMemory &m) {
  if (filter_) filter_->restore(m);
  if (m.filterOverride >= static_cast<int>(EigenFilterMode::Clamp) &&
      m.filterOverride <= static_cast<int>(EigenFilterMode::Abs))
    overrideFilter(static_cast<EigenFilterMode>(m.filterOverride));
  else
    restoreFilter();
}

PetscErrorCode NewtonSolver::energyAt(Vec x, PetscReal *value, PetscReal *magnitude) {
  return ctx_.energyAt(x, value, magnitude);
}

PetscErrorCode NewtonSolver::objectiveCallback(SNES, Vec x, PetscReal *value, void *ctx) {
  PetscFunctionBeginUser;
  PetscCall(static_cast<NewtonSolver *>(ctx)->ctx_.energyAt(x, value, nullptr));
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonSolver::alphasAt(Vec xGlobal, std::vector<double> *alpha) {
  return safeguard_->alphasAt(ctx_, xGlobal, alpha);
}

PetscErrorCode NewtonSolver::alphaAcceptable(Vec xGlobal, const std::vector<double> &reference, bool *ok) {
  return safeguard_->acceptable(ctx_, xGlobal, reference, ok);
}

// ---- the strategies around each line search -----------------------------------------------------------------------

// Before every line search (of any type): the iteration's record, then the strategies in their order. A direction
// the convergence check accepts is the final correction: applied here (stepIfResidualDrops), its length what the
// safeguard left of it (the history row's lambda; 0 if not applied), then SNES stops after the (empty) line search on
// the reason the check set, without counting an iteration.
PetscErrorCode NewtonSolver::preCheck(SNESLineSearch, Vec X, Vec Y, PetscBool *changed, void *ctx) {
  auto *self = static_cast<NewtonSolver *>(ctx);
  NewtonContext &c = self->ctx_;
  KSP ksp;
  KSPConvergedReason linearReason;
  PetscInt its, iter;
  Vec F;
  PetscFunctionBeginUser;
  *changed = PETSC_FALSE;
  PetscCall(SNESGetKSP(c.snes, &ksp));
  PetscCall(KSPGetConvergedReason(ksp, &linearReason));
  PetscCall(KSPGetIterationNumber(ksp, &its));
  PetscCall(SNESGetIterationNumber(c.snes, &iter));
  PetscCall(SNESGetFunction(c.snes, &F, nullptr, nullptr));
  c.countLinearSolve(linearReason);
  if (self->opts_.local.maxIterations > 0) {  // the local solve measures the update against it
    if (!self->local_.before) PetscCall(VecDuplicate(X, &self->local_.before));
    PetscCall(VecCopy(X, self->local_.before));
  }
  const PetscInt solvesBefore = c.result.linearSolves;
  PetscCall(c.finishSystem(ksp, F, Y));  // may solve it again with a new preconditioner
  if (c.result.linearSolves != solvesBefore) *changed = PETSC_TRUE;
  PetscCall(KSPGetConvergedReason(ksp, &linearReason));
  PetscCall(KSPGetIterationNumber(ksp, &its));
  Direction &d = self->pending_;
  d = Direction{};
  d.record.iteration = iter + c.iterationOffset;
  d.record.load = c.disc->load();
  d.record.linearIterations = its;
  d.record.preconditionerBuilt = c.preconditioner.built();
  d.record.filter = filterTag(c.disc->eigenFilter());
  PetscCall(VecNorm(F, NORM_2, &d.record.residual));
  self->havePending_ = true;

  PetscCall(self->filter_->repairDirection(c, d, X, Y, F, changed));
  const PetscInt halvingsBefore = c.result.safeguardHalvings;
  for (auto &step : self->steps_) {
    if (d.finalCorrection && !step->appliesToFinalCorrection()) continue;
    PetscCall(step->shapeDirection(c, d, X, Y, F, changed));
  }
  if (d.finalCorrection) {
    self->havePending_ = false;
    bool applied = false;
    PetscCall(self->stepIfResidualDrops(X, Y, F, &applied));
    d.record.lambda = applied ? std::ldexp(1.0, -static_cast<int>(c.result.safeguardHalvings - halvingsBefore)) : 0.0;
    c.result.history.push_back(d.record);
    PetscCall(VecSet(Y, 0.0));  // the line search that follows has nothing left to do; SNES stops on the reason
    *changed = PETSC_TRUE;
    PetscFunctionReturn(0);
  }
  // A direction along which the energy changes by less than its round-off (near the solution at a tight -newton_tol):
  // the energy line search would accept or reject it by chance. It is judged by the gradient instead: taken in full
  // where it lowers |g|, the line search then left nothing to do (the convergence test knows it was not a failure).
  PetscScalar slope;
  PetscCall(VecDot(F, Y, &slope));
  if (std::abs(slope) <= kFlatDirectionFactor * d.roundoff) {
    bool applied = false;
    PetscCall(self->stepIfResidualDrops(X, Y, F, &applied));
    if (applied) {
      d.residualStep = true;
      PetscCall(VecSet(Y, 0.0));
      *changed = PETSC_TRUE;
    }
  }
  PetscFunctionReturn(0);
}

// The direction Y (shaped by the safeguard) applied in full, X <- X - Y, where it lowers the norm of the
// gradient: near the solution an exact Newton step cuts it (quadratically) where the energy's change is round-off.
// F follows X (the run's reported residual is the final state's).
PetscErrorCode NewtonSolver::stepIfResidualDrops(Vec X, Vec Y, Vec F, bool *applied) {
  PetscReal before, after;
  PetscFunctionBeginUser;
  *applied = false;
  PetscCall(VecWAXPY(ctx_.trialX, -1.0, Y, X));
  PetscCall(SNESComputeFunction(ctx_.snes, ctx_.trialX, ctx_.trialF));
  PetscCall(VecNorm(F, NORM_2, &before));
  PetscCall(VecNorm(ctx_.trialF, NORM_2, &after));
  if (!(after < before)) PetscFunctionReturn(0);  // NaN too; a zero direction changes nothing and is no update
  PetscCall(VecCopy(ctx_.trialX, X));
  PetscCall(VecCopy(ctx_.trialF, F));
  *applied = true;
  PetscFunctionReturn(0);
}

// After every line search (of any type): the strategies' checks of the accepted point (the alpha safeguard).
PetscErrorCode NewtonSolver::postCheck(SNESLineSearch, Vec X, Vec, Vec W, PetscBool *changedY, PetscBool *changedW,
                                       void *ctx) {
  auto *self = static_cast<NewtonSolver *>(ctx);
  PetscFunctionBeginUser;
  *changedY = PETSC_FALSE;
  *changedW = PETSC_FALSE;
  if (self->ctx_.result.convergence != Convergence::None) PetscFunctionReturn(0);
  for (auto &step : self->steps_) PetscCall(step->checkPoint(self->ctx_, self->pending_, X, W, changedW));
  PetscFunctionReturn(0);
}

// After an update: its record (lambda = the line search's length times the share the safeguard kept), then every
// strategy's finishUpdate.
PetscErrorCode NewtonSolver::finishUpdate(Vec xNew) {
  SNESLineSearch ls;
  PetscReal lambda;
  PetscFunctionBeginUser;
  if (!havePending_) PetscFunctionReturn(0);
  havePending_ = false;
  PetscCall(SNESGetLineSearch(ctx_.snes, &ls));
  PetscCall(SNESLineSearchGetLambda(ls, &lambda));
  if (pending_.residualStep) lambda = 1.0;  // taken in full before the (then empty) line search
  lambda *= pending_.postScale;
  pending_.record.lambda = lambda;
  ctx_.result.history.push_back(pending_.record);
  for (auto &step : steps_) PetscCall(step->finishUpdate(ctx_, pending_, xNew, lambda));
  PetscFunctionReturn(0);
}

// PETSc's tests as configured (atol; rtol and stol are 0 unless the user sets them), NaN, max_it; the bookkeeping
// of the update that just finished; the convergence check's test of the iterate (backward Euler's step bound).
PetscErrorCode NewtonSolver::convergenceTest(SNES snes, PetscInt it, PetscReal xnorm, PetscReal snorm,
                                             PetscReal fnorm, SNESConvergedReason *reason, void *ctx) {
  auto *self = static_cast<NewtonSolver *>(ctx);
  PetscFunctionBeginUser;
  PetscCall(SNESConvergedDefault(snes, it, xnorm, snorm, fnorm, reason, nullptr));
  if (*reason > 0) self->ctx_.result.convergence = Convergence::Petsc;
  if (it > 0 && self->havePending_ && !self->pending_.residualStep) {
    // SNES lets line searches fail (-snes_max_fail is raised for the residual steps, whose line search has nothing to
    // do): a failure of a real one ends the solve as before, its record kept by solve() and no update counted.
    SNESLineSearch ls;
    SNESLineSearchReason lsReason;
    PetscCall(SNESGetLineSearch(snes, &ls));
    PetscCall(SNESLineSearchGetReason(ls, &lsReason));
    if (lsReason != SNES_LINESEARCH_SUCCEEDED) {
      *reason = SNES_DIVERGED_LINE_SEARCH;
      PetscFunctionReturn(0);
    }
  }
  if (it > 0) {
    Vec x;
    self->ctx_.result.newtonIterations = it + self->ctx_.iterationOffset;
    PetscCall(SNESGetSolution(snes, &x));
    PetscCall(self->finishUpdate(x));
    if (*reason == SNES_CONVERGED_ITERATING && self->opts_.local.maxIterations > 0) {
      Vec F;
      PetscCall(SNESGetFunction(snes, &F, nullptr, nullptr));
      PetscCall(self->localSolve(x, F, &fnorm));
    }
  }
  PetscCall(self->check_->testIterate(self->ctx_, it, fnorm, reason));
  PetscFunctionReturn(0);
}

}  // namespace aries::solver
