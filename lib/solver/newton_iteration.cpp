// One Newton iteration of NewtonSolver (newton.hpp): the model callbacks (energy, gradient, filtered Hessian),
// the alpha safeguard, the convergence tests on the Newton direction, the subspace step and the bookkeeping of each
// update. Setup, options and the solve loop are in newton.cpp.
#include "solver/newton.hpp"
#include "solver/local_vec.hpp"

#include "core/options.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

namespace aries::solver {

namespace {

// A CG iterate this many times the step tolerance is a step that cannot be the last: its solve may stop early
// (-newton_forcing).
constexpr double kForcingMargin = 2.0;
// Checking the iterate costs a reduction: look every few CG iterations.
constexpr PetscInt kForcingCheckEvery = 5;
// The subspace step needs its (scaled) Gram matrix this well conditioned (smallest / largest eigenvalue).
constexpr double kSubspaceConditioning = 1e-8;
// The alpha safeguard guards a cell only from kGuardMargin * alpha_min up (see alphaAcceptable).
constexpr double kGuardMargin = 2.0;


}  // namespace

// ---- callbacks of the model -------------------------------------------------------------------------------------

PetscErrorCode NewtonSolver::boundaryLocal(DM, Vec xLocal, void *ctx) {
  PetscFunctionBeginUser;
  PetscCall(static_cast<NewtonSolver *>(ctx)->disc_->fillBoundary(xLocal));
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonSolver::functionLocal(DM, Vec xLocal, Vec gLocal, void *ctx) {
  auto *self = static_cast<NewtonSolver *>(ctx);
  PetscFunctionBeginUser;
  PetscCall(PetscLogStagePush(self->assemblyStage_));
  PetscCall(self->disc_->gradient(xLocal, gLocal));
  PetscCall(PetscLogStagePop());
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonSolver::jacobianLocal(DM, Vec xLocal, Mat, Mat P, void *ctx) {
  auto *self = static_cast<NewtonSolver *>(ctx);
  PetscFunctionBeginUser;
  PetscCall(PetscLogStagePush(self->assemblyStage_));
  PetscCall(self->disc_->hessian(xLocal, P));
  PetscCall(PetscLogStagePop());
  if (self->useInertiaGuess_) PetscCall(self->inertiaGuess(P));
  PetscFunctionReturn(0);
}

// Backward Euler: the linear solve H p = g starts from the inertia-only step scaled optimally in the H-norm,
// p0 = a M^-1 g with a = (g^T M^-1 g) / ((M^-1 g)^T H M^-1 g): never worse than a zero start in the H-norm, and exact
// for a rigid translation (free fall), where CG then has nothing left to do.
PetscErrorCode NewtonSolver::inertiaGuess(Mat H) {
  Vec g, p;
  KSP ksp;
  PetscScalar gv, vHv;
  PetscFunctionBeginUser;
  PetscCall(SNESGetFunction(snes_, &g, nullptr, nullptr));
  PetscCall(SNESGetSolutionUpdate(snes_, &p));
  PetscCall(SNESGetKSP(snes_, &ksp));
  PetscCall(VecPointwiseMult(p, g, invMass_));
  PetscCall(MatMult(H, p, work_));
  PetscCall(VecDot(g, p, &gv));
  PetscCall(VecDot(p, work_, &vHv));
  const bool usable = vHv > 0.0 && gv > 0.0;
  if (usable) PetscCall(VecScale(p, gv / vHv));
  PetscCall(KSPSetInitialGuessNonzero(ksp, usable ? PETSC_TRUE : PETSC_FALSE));
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonSolver::energyAt(Vec x, PetscReal *value, PetscReal *magnitude) {
  LocalVec xl(disc_->dm());
  PetscFunctionBeginUser;
  PetscCall(PetscLogStagePush(assemblyStage_));
  PetscCall(xl.fromGlobal(x, disc_));
  PetscCall(disc_->objective(xl.get(), value, magnitude));
  PetscCall(PetscLogStagePop());
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonSolver::objectiveCallback(SNES, Vec x, PetscReal *value, void *ctx) {
  PetscFunctionBeginUser;
  PetscCall(static_cast<NewtonSolver *>(ctx)->energyAt(x, value, nullptr));
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonSolver::gram(Vec X, const std::vector<Vec> &directions, std::vector<double> *G) {
  const DM dm = disc_->dm();
  LocalVec xl(dm);
  std::vector<std::unique_ptr<LocalVec>> dl;
  std::vector<Vec> d(directions.size());
  PetscFunctionBeginUser;
  PetscCall(xl.fromGlobal(X, disc_));
  for (size_t k = 0; k < directions.size(); ++k) {
    dl.push_back(std::make_unique<LocalVec>(dm));
    PetscCall(dl[k]->fromGlobal(directions[k], nullptr));
    d[k] = dl[k]->get();
  }
  PetscCall(PetscLogStagePush(assemblyStage_));
  PetscCall(disc_->curvatureGram(xl.get(), d, G));
  PetscCall(PetscLogStagePop());
  PetscFunctionReturn(0);
}

// ---- the alpha safeguard ----------------------------------------------------------------------------------------

PetscErrorCode NewtonSolver::alphasAt(Vec xGlobal, std::vector<double> *alpha) {
  LocalVec xl(disc_->dm());
  PetscFunctionBeginUser;
  PetscCall(xl.fromGlobal(xGlobal, disc_));
  PetscCall(disc_->cellGuard(xl.get(), alpha));
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonSolver::alphaAcceptable(Vec xGlobal, const std::vector<double> &reference, bool *ok) {
  std::vector<double> alpha;
  MPI_Comm comm;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)xGlobal, &comm));
  PetscCall(alphasAt(xGlobal, &alpha));
  disc_->mollifierBandTop(&bandTop_);
  // Paper Sec. 4.2: a step must not *cause* alpha to become less than the threshold. Cells inside their singular
  // band already (an inside-out start has alpha = 0 everywhere; the mollifier's flat region alpha < eps) are left to
  // the energy and its line search, and a guarded cell starts at least 2 alpha_min above zero: guarding cells that
  // hover just above the bound lets any one of thousands of them veto every direction, and the step is halved to
  // nothing (a deadlock). With the margin every guarded cell admits a step of length ~ alpha_min / |d alpha/d step|.
  int bad = 0;
  for (size_t c = 0; c < alpha.size() && !bad; ++c) {
    const bool guarded = reference[c] >= std::max(kGuardMargin * alphaMin_, bandTop_[c]);
    bad = std::isnan(alpha[c]) || (guarded && !(alpha[c] >= alphaMin_));
  }
  int anyBad = 0;
  PetscCallMPI(MPI_Allreduce(&bad, &anyBad, 1, MPI_INT, MPI_MAX, comm));
  *ok = !anyBad;
  PetscFunctionReturn(0);
}

// Halves the direction until the full step keeps every guarded element's alpha acceptable.
PetscErrorCode NewtonSolver::safeguard(Vec X, Vec Y, PetscBool *changed) {
  PetscFunctionBeginUser;
  PetscCall(alphasAt(X, &alphaRef_));
  for (int k = 0; k < 60; ++k) {
    PetscCall(VecWAXPY(work_, -1.0, Y, X));
    bool ok = false;
    PetscCall(alphaAcceptable(work_, alphaRef_, &ok));
    if (ok) break;
    PetscCall(VecScale(Y, 0.5));
    slope_ *= 0.5;
    curvatureFull_ *= 0.25;
    *changed = PETSC_TRUE;
    halved_ = true;
    ++cur_.safeguardHalvings;
  }
  PetscFunctionReturn(0);
}

// ---- convergence ------------------------------------------------------------------------------------------------

// Backward Euler: H = M / dt^2 + K with K PSD (filtered), so with D = M / dt^2, p = H^-1 g satisfies
// p^T D p <= p^T H p = g^T H^-1 g <= g^T D^-1 g, hence |p_i| <= sqrt(g^T D^-1 g / D_ii) for every dof i:
// |p|_inf <= sqrt(g^T M^-1 g) dt^2 / sqrt(min_i m_i). Infinite where no such bound holds.
PetscErrorCode NewtonSolver::stepBound(Vec g, PetscReal *bound) {
  PetscScalar gMg;
  PetscFunctionBeginUser;
  *bound = PETSC_INFINITY;
  if (!dynamic_ || filterMode_ == EigenFilterMode::None || !(minMass_ > 0.0)) PetscFunctionReturn(0);
  PetscCall(VecPointwiseMult(work_, g, invMass_));
  PetscCall(VecDot(work_, g, &gMg));
  *bound = std::sqrt(std::max(0.0, (double)gMg)) * dt_ * dt_ / std::sqrt(minMass_);
  PetscFunctionReturn(0);
}

void NewtonSolver::declareConverged(Convergence how) {
  cur_.convergence = how;
  SNESSetConvergedReason(snes_, SNES_CONVERGED_SNORM_RELATIVE);
}

// Is the state converged on the Newton direction Y (g . Y >= 0 descends along -Y)? A loose linear solve underestimates
// the Newton step (CG iterates grow in norm from a zero start), so a small loose step certifies only with a bound on
// its error (backward Euler: the step bound of the linear residual) or after a solve at the base tolerance.
PetscErrorCode NewtonSolver::certify(Vec X, Vec Y, Vec F, PetscInt iter, bool *converged) {
  KSP ksp;
  KSPConvergedReason linearReason;
  PetscReal stepInf, energy, magnitude, rtol;
  PetscScalar slope;
  PetscFunctionBeginUser;
  *converged = false;
  PetscCall(SNESGetKSP(snes_, &ksp));
  PetscCall(KSPGetConvergedReason(ksp, &linearReason));
  PetscCall(VecNorm(Y, NORM_INFINITY, &stepInf));
  PetscCall(VecDot(F, Y, &slope));
  PetscCall(energyAt(X, &energy, &magnitude));
  pending_.energy = energy;
  pending_.stepInf = stepInf;
  energyBefore_ = energy;
  slope_ = slope;
  // Round-off of the summed energy: machine epsilon times the sum of the magnitudes of its terms, with a safety factor
  // for the accumulation over many terms. A predicted decrease below it cannot be measured by any line search.
  DirectionMeasures m;
  m.linearConverged = linearReason > 0;
  m.iteration = static_cast<int>(iter);
  m.stepInf = stepInf;
  m.stepTol = stepTol_;
  m.slope = slope;
  m.roundoff = 1e3 * kernels::kEps * magnitude;
  Convergence how = classifyDirection(m);
  PetscCall(KSPGetTolerances(ksp, &rtol, nullptr, nullptr, nullptr));
  const bool loose = rtol > baseRtol_ || forcingStopped_;
  const bool small = how == Convergence::Initial || how == Convergence::NewtonStep;
  if (how != Convergence::None && loose) {
    bool bounded = false;
    if (small && dynamic_) {
      PetscReal errorBound;
      PetscCall(MatMult(J_, Y, work_));
      PetscCall(VecAYPX(work_, -1.0, F));  // the linear residual r = g - H p
      PetscCall(stepBound(work_, &errorBound));
      bounded = stepInf + errorBound <= stepTol_;
    }
    if (!bounded) {  // solve again at the base tolerance, from the loose solution
      PetscBool ew, guess;
      PetscCall(SNESKSPGetUseEW(snes_, &ew));
      PetscCall(KSPGetInitialGuessNonzero(ksp, &guess));
      PetscCall(SNESKSPSetUseEW(snes_, PETSC_FALSE));
      PetscCall(KSPSetTolerances(ksp, baseRtol_, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT));
      PetscCall(KSPSetInitialGuessNonzero(ksp, PETSC_TRUE));
      const double keepForcing = forcing_;
      forcing_ = 0.0;
      PetscCall(KSPSolve(ksp, F, Y));
      forcing_ = keepForcing;
      PetscCall(KSPSetInitialGuessNonzero(ksp, guess));
      PetscCall(SNESKSPSetUseEW(snes_, ew));
      PetscCall(KSPGetConvergedReason(ksp, &linearReason));
      ++cur_.linearSolves;
      if (linearReason == KSP_DIVERGED_ITS) ++cur_.linearAtLimit;
      PetscCall(VecNorm(Y, NORM_INFINITY, &stepInf));
      PetscCall(VecDot(F, Y, &slope));
      pending_.stepInf = stepInf;
      slope_ = slope;
      m.linearConverged = linearReason > 0;
      m.stepInf = stepInf;
      m.slope = slope;
      how = classifyDirection(m);
    }
  }
  if (how != Convergence::None) {
    declareConverged(how);
    *converged = true;
  }
  PetscFunctionReturn(0);
}

// PETSc's tests as configured (atol; rtol and stol are 0 unless the user sets them), NaN, max_it; the step bound of
// backward Euler; and the bookkeeping of the update that just finished.
PetscErrorCode NewtonSolver::convergenceTest(SNES snes, PetscInt it, PetscReal xnorm, PetscReal snorm,
                                             PetscReal fnorm, SNESConvergedReason *reason, void *ctx) {
  auto *self = static_cast<NewtonSolver *>(ctx);
  PetscFunctionBeginUser;
  PetscCall(SNESConvergedDefault(snes, it, xnorm, snorm, fnorm, reason, nullptr));
  if (*reason > 0) self->cur_.convergence = Convergence::Petsc;
  if (it > 0) {
    Vec x;
    self->cur_.newtonIterations = it;
    PetscCall(SNESGetSolution(snes, &x));
    PetscCall(self->finishUpdate(x));
  }
  if (*reason == SNES_CONVERGED_ITERATING || *reason == SNES_DIVERGED_MAX_IT) {
    Vec g;
    PetscReal bound;
    PetscCall(SNESGetFunction(snes, &g, nullptr, nullptr));
    PetscCall(self->stepBound(g, &bound));
    if (bound <= self->stepTol_) {
      self->cur_.convergence = it == 0 ? Convergence::Initial : Convergence::StepBound;
      *reason = SNES_CONVERGED_SNORM_RELATIVE;
      IterationRecord rec;
      Vec x;
      rec.iteration = it;
      rec.residual = fnorm;
      rec.stepInf = bound;  // a bound, not the step
      PetscCall(SNESGetSolution(snes, &x));
      PetscCall(self->energyAt(x, &rec.energy, nullptr));
      self->cur_.history.push_back(rec);
    }
  }
  PetscFunctionReturn(0);
}

// Inexact Newton with a step-aware stop (-newton_forcing eta): CG stops once its relative residual is below eta if
// its iterate already shows a Newton step well above the convergence tolerance (this cannot be the last direction);
// a direction that could certify convergence is always solved to -ksp_rtol.
PetscErrorCode NewtonSolver::linearConvergence(KSP ksp, PetscInt it, PetscReal rnorm, KSPConvergedReason *reason,
                                               void *ctx) {
  auto *self = static_cast<NewtonSolver *>(ctx);
  PetscFunctionBeginUser;
  PetscCall(KSPConvergedDefault(ksp, it, rnorm, reason, self->defaultKspCtx_));
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
      PetscCall(PCApply(pc, b, self->work_));
      PetscCall(VecNorm(self->work_, NORM_2, &self->rnorm0_));
    }
  }
  if (*reason != KSP_CONVERGED_ITERATING || !(self->forcing_ > 0.0) || it == 0 || it % kForcingCheckEvery)
    PetscFunctionReturn(0);
  if (!(rnorm <= self->forcing_ * self->rnorm0_)) PetscFunctionReturn(0);
  Vec x;
  PetscReal xinf;
  PetscCall(KSPBuildSolution(ksp, nullptr, &x));
  PetscCall(VecNorm(x, NORM_INFINITY, &xinf));
  if (xinf > kForcingMargin * self->stepTol_) {
    *reason = KSP_CONVERGED_RTOL;
    self->forcingStopped_ = true;
  }
  PetscFunctionReturn(0);
}

// ---- the update -------------------------------------------------------------------------------------------------

// Subspace step: minimize the true quadratic model m(u) = -g.u... over u = -(c_0 Y + sum_j c_j D_j), D_j = -s_j the
// previous updates s_j (newest first): G c = r with G_kl = D_k^T H D_l (exact Hessian) and r_k = g . D_k. The largest
// leading block of G that is positive definite is used; the step must keep a positive Newton coefficient c_0.
PetscErrorCode NewtonSolver::accelerate(Vec X, Vec Y, Vec F, PetscBool *changed) {
  PetscFunctionBeginUser;
  if (cur_.history.empty() || subspace_ <= 0) {  // first direction of the solve: nothing to combine with yet
    PetscCall(VecCopy(X, prevX_));
    PetscFunctionReturn(0);
  }
  // newest update first
  Vec oldest = history_.back();
  for (size_t j = history_.size() - 1; j > 0; --j) history_[j] = history_[j - 1];
  history_[0] = oldest;
  PetscCall(VecWAXPY(history_[0], -1.0, prevX_, X));
  PetscCall(VecCopy(X, prevX_));
  historyCount_ = std::min<PetscInt>(historyCount_ + 1, subspace_);
  // A limited subspace step (static solves) is taken only after an update the line search accepted in full.
  if (subspaceMax_ > 0.0 && !lastFull_) PetscFunctionReturn(0);

  const int K = 1 + static_cast<int>(historyCount_);
  std::vector<Vec> dirs(K);
  dirs[0] = Y;
  for (int k = 1; k < K; ++k) dirs[k] = history_[k - 1];
  std::vector<double> G;
  PetscCall(gram(X, dirs, &G));
  Eigen::VectorXd r(K);
  Eigen::MatrixXd A(K, K);
  r[0] = slope_;
  for (int k = 1; k < K; ++k) {
    PetscScalar gs;
    PetscCall(VecDot(F, history_[k - 1], &gs));
    r[k] = -gs;
  }
  for (int k = 0; k < K; ++k)
    for (int l = 0; l < K; ++l) A(k, l) = (k == 0 ? 1.0 : -1.0) * (l == 0 ? 1.0 : -1.0) * G[k * K + l];
  int use = K;
  Eigen::VectorXd c;
  for (; use >= 2; --use) {
    // Positive definite and well conditioned: nearly parallel directions would turn round-off into large, cancelling
    // coefficients (and results that depend on the partition's summation order).
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(A.topLeftCorner(use, use));
    const Eigen::VectorXd &ev = eig.eigenvalues();
    if (!(ev[0] > kSubspaceConditioning * ev[use - 1])) continue;
    c = eig.eigenvectors() * (eig.eigenvectors().transpose() * r.head(use)).cwiseQuotient(ev);
    if (c[0] > 0.0) break;
  }
  if (use < 2) PetscFunctionReturn(0);
  if (subspaceMax_ > 0.0 && c[0] > subspaceMax_) c *= subspaceMax_ / c[0];
  PetscCall(VecCopy(Y, newtonDir_));
  PetscCall(VecScale(Y, c[0]));
  for (int k = 1; k < use; ++k) PetscCall(VecAXPY(Y, -c[k], history_[k - 1]));
  PetscScalar slope;
  PetscCall(VecDot(F, Y, &slope));
  if (subspaceMax_ > 0.0) {
    // A limited subspace step must decrease the energy at full length (Armijo); otherwise the Newton direction goes
    // to the line search unchanged.
    PetscReal eNew;
    PetscCall(VecWAXPY(work_, -1.0, Y, X));
    PetscCall(energyAt(work_, &eNew, nullptr));
    if (!(eNew <= energyBefore_ - 1e-4 * slope)) {
      PetscCall(VecCopy(newtonDir_, Y));
      PetscFunctionReturn(0);
    }
  }
  slope_ = slope;
  // curvature of the combined step for the adaptive filter's ratio: c^T A c
  curvatureFull_ = c.dot(A.topLeftCorner(use, use) * c);
  haveCurvature_ = true;
  pending_.accelerated = true;
  *changed = PETSC_TRUE;
  PetscFunctionReturn(0);
}

// Runs before every line search (of any type): the convergence test on the Newton direction, the subspace step, the
// data the adaptive filter judges the update by, then the alpha safeguard (paper Sec. 4.2).
PetscErrorCode NewtonSolver::preCheck(SNESLineSearch, Vec X, Vec Y, PetscBool *changed, void *ctx) {
  auto *self = static_cast<NewtonSolver *>(ctx);
  KSP ksp;
  KSPConvergedReason linearReason;
  PetscInt its, iter;
  Vec F;
  PetscFunctionBeginUser;
  *changed = PETSC_FALSE;
  PetscCall(SNESGetKSP(self->snes_, &ksp));
  PetscCall(KSPGetConvergedReason(ksp, &linearReason));
  PetscCall(KSPGetIterationNumber(ksp, &its));
  PetscCall(SNESGetIterationNumber(self->snes_, &iter));
  PetscCall(SNESGetFunction(self->snes_, &F, nullptr, nullptr));
  ++self->cur_.linearSolves;
  if (linearReason == KSP_DIVERGED_ITS) ++self->cur_.linearAtLimit;
  IterationRecord &rec = self->pending_;
  rec = IterationRecord{};
  rec.iteration = iter;
  rec.linearIterations = its;
  rec.filter = self->disc_->eigenFilter() == kernels::EigenFilter::Abs    ? 'a'
               : self->disc_->eigenFilter() == kernels::EigenFilter::None ? 'n'
                                                                           : 'c';
  PetscCall(VecNorm(F, NORM_2, &rec.residual));
  self->havePending_ = true;
  self->halved_ = false;
  self->postScale_ = 1.0;
  self->haveCurvature_ = false;

  if (self->floating_) PetscCall(self->removeRigidMotion(X, Y));
  bool converged = false;
  PetscCall(self->certify(X, Y, F, iter, &converged));
  if (converged) {
    // SNES stops after this line search on the reason set by certify, without counting an iteration. A Newton step
    // below the tolerance is applied as a final correction (it is an exact solve's step: the line search takes it in
    // full, the safeguard still applies; its length is the history row's lambda); a direction converged by
    // round-off is not (lambda 0).
    self->havePending_ = false;
    if (self->cur_.convergence == Convergence::EnergyRoundoff) {
      PetscCall(VecSet(Y, 0.0));
      *changed = PETSC_TRUE;
    } else {
      const PetscInt halvingsBefore = self->cur_.safeguardHalvings;
      PetscCall(self->safeguard(X, Y, changed));
      rec.lambda = std::ldexp(1.0, -static_cast<int>(self->cur_.safeguardHalvings - halvingsBefore));
    }
    self->cur_.history.push_back(rec);
    PetscFunctionReturn(0);
  }
  PetscCall(self->accelerate(X, Y, F, changed));
  PetscCall(self->rotate(X, Y, F, changed));
  if (self->filterMode_ == EigenFilterMode::Adaptive && !self->haveCurvature_) {
    std::vector<double> G;
    PetscCall(self->gram(X, {Y}, &G));
    self->curvatureFull_ = G[0];
    self->haveCurvature_ = true;
  }
  PetscCall(self->safeguard(X, Y, changed));
  PetscFunctionReturn(0);
}

// After every line search (of any type): the alpha safeguard on the accepted point (line searches that extrapolate,
// l2 and cp, can leave the checked segment). PETSc's bt line search hands over Y already scaled by its length (and
// resets its length afterwards), the others do not: the point is halved towards X in place, W <- (W + X) / 2, which
// is right for both, and finishUpdate records the length kept.
PetscErrorCode NewtonSolver::postCheck(SNESLineSearch, Vec X, Vec, Vec W, PetscBool *changedY,
                                       PetscBool *changedW, void *ctx) {
  auto *self = static_cast<NewtonSolver *>(ctx);
  PetscFunctionBeginUser;
  *changedY = PETSC_FALSE;
  *changedW = PETSC_FALSE;
  if (self->cur_.convergence != Convergence::None) PetscFunctionReturn(0);
  for (int k = 0; k < 60; ++k) {
    bool ok = false;
    PetscCall(self->alphaAcceptable(W, self->alphaRef_, &ok));
    if (ok) break;
    PetscCall(VecAXPBY(W, 0.5, 0.5, X));
    self->postScale_ *= 0.5;
    *changedW = PETSC_TRUE;
    self->halved_ = true;
    ++self->cur_.safeguardHalvings;
  }
  PetscFunctionReturn(0);
}

// After an update: record it; the adaptive filter's trust-region ratio (Chen et al. 2024) rho = actual / predicted
// decrease with the true quadratic model of the update taken picks the next filter: clamp where the model is
// trustworthy (|rho - 1| < -psd_adaptive_tol: fast local convergence), abs otherwise (robust far from equilibrium);
// a limited subspace step (static solves) waits for an update accepted in full.
PetscErrorCode NewtonSolver::finishUpdate(Vec xNew) {
  SNESLineSearch ls;
  PetscReal lambda;
  PetscFunctionBeginUser;
  if (!havePending_) PetscFunctionReturn(0);
  havePending_ = false;
  PetscCall(SNESGetLineSearch(snes_, &ls));
  PetscCall(SNESLineSearchGetLambda(ls, &lambda));
  lambda *= postScale_;  // postCheck's share of the line search's length
  pending_.lambda = lambda;
  cur_.history.push_back(pending_);
  lastFull_ = lambda >= 1.0 && !halved_;
  if (filterMode_ == EigenFilterMode::Adaptive && haveCurvature_) {
    PetscReal energy;
    PetscCall(energyAt(xNew, &energy, nullptr));
    const double predicted = lambda * slope_ - 0.5 * lambda * lambda * curvatureFull_;
    const double rho = predicted != 0.0 ? (energyBefore_ - energy) / predicted : 0.0;
    disc_->setEigenFilter(std::abs(rho - 1.0) < adaptiveTol_ ? kernels::EigenFilter::Clamp : kernels::EigenFilter::Abs);
  }
  PetscFunctionReturn(0);
}

}  // namespace aries::solver
