// 6. AlphaSafeguard (newton_steps.hpp, -alpha_min; paper Sec. 4.2): no accepted step takes an element whose alpha is
// at or above the top of its singular band to below -alpha_min; the direction is halved until it holds before the
// line search, and the accepted point after it. The band is [0, mollifier eps) for elements evaluated with the
// mollifier (there the I4/I6 terms are the constant proxy and nothing is singular) and [0, alpha_min) otherwise, so
// elements already inside it never block a step.
#include "solver/local_vec.hpp"
#include "solver/newton_steps.hpp"

#include <algorithm>
#include <cmath>

namespace aries::solver {

namespace {
// The alpha safeguard guards a cell only from kGuardMargin * alpha_min up (see AlphaSafeguard::acceptable).
constexpr double kGuardMargin = 2.0;
// More halvings than this leave no step worth taking (2^-60).
constexpr int kMaxSafeguardHalvings = 60;
}  // namespace

// alpha is a function of the local state alone (the cells' deformation gradients): a state equal in every local value
// to the last one evaluated, on the same discretization, has its alphas. The comparison is per rank and needs no
// communication (the scatter before it is collective either way).
PetscErrorCode AlphaSafeguard::alphasAt(NewtonContext &ctx, Vec xGlobal, std::vector<double> *alpha) {
  LocalVec xl(ctx.disc->dm());
  bool sameState = false;
  PetscFunctionBeginUser;
  PetscCall(xl.fromGlobal(xGlobal, ctx.disc));
  PetscCall(memoState_.matches(xl.get(), &sameState));
  ctx.disc->mollifierBandTop(&bandTop_);  // the bands move with the barrier's fallback (at a step's start)
  const double cap = exactBelow(bandTop_);
  if (!(sameState && memoDisc_ == ctx.disc && memoExactBelow_ == cap)) {
    memoDisc_ = nullptr;  // until the alphas below exist
    PetscCall(ctx.disc->cellGuard(xl.get(), cap, &memoAlpha_));
    memoDisc_ = ctx.disc;
    memoExactBelow_ = cap;
  }
  *alpha = memoAlpha_;
  PetscFunctionReturn(0);
}

PetscErrorCode AlphaSafeguard::acceptable(NewtonContext &ctx, Vec xGlobal, const std::vector<double> &reference,
                                          bool *ok) {
  std::vector<double> alpha;
  MPI_Comm comm;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)xGlobal, &comm));
  PetscCall(alphasAt(ctx, xGlobal, &alpha));  // bandTop_ too
  // Paper Sec. 4.2: a step must not *cause* alpha to become less than the threshold. Cells inside their singular
  // band already (an inside-out start has alpha = 0 everywhere; the mollifier's flat region alpha < eps) are left to
  // the energy and its line search, and a guarded cell starts at least 2 alpha_min above zero: guarding cells that
  // hover just above the bound lets any one of thousands of them veto every direction, and the step is halved to
  // nothing (a deadlock). With the margin every guarded cell admits a step of length ~ alpha_min / |d alpha/d step|.
  int bad = rejects(reference, alpha, bandTop_) ? 1 : 0;
  int anyBad = 0;
  PetscCallMPI(MPI_Allreduce(&bad, &anyBad, 1, MPI_INT, MPI_MAX, comm));
  *ok = !anyBad;
  PetscFunctionReturn(0);
}

double AlphaSafeguard::exactBelow(const std::vector<double> &bandTop) const {
  double top = kGuardMargin * opts_.alphaMin;  // the guarded test's; alpha_min itself is below it
  for (double b : bandTop) top = std::max(top, b);
  return top;
}

bool AlphaSafeguard::rejects(const std::vector<double> &reference, const std::vector<double> &alpha,
                             const std::vector<double> &bandTop) const {
  for (size_t c = 0; c < alpha.size(); ++c) {
    const bool guarded = reference[c] >= std::max(kGuardMargin * opts_.alphaMin, bandTop[c]);
    if (std::isnan(alpha[c]) || (guarded && !(alpha[c] >= opts_.alphaMin))) return true;
  }
  return false;
}

// Halves the direction until the full step keeps every guarded element's alpha acceptable.
PetscErrorCode AlphaSafeguard::shapeDirection(NewtonContext &ctx, Direction &d, Vec X, Vec Y, Vec, PetscBool *changed) {
  PetscFunctionBeginUser;
  PetscCall(alphasAt(ctx, X, &alphaRef_));
  for (int k = 0; k < kMaxSafeguardHalvings; ++k) {
    PetscCall(VecWAXPY(ctx.work, -1.0, Y, X));
    bool ok = false;
    PetscCall(acceptable(ctx, ctx.work, alphaRef_, &ok));
    if (ok) break;
    PetscCall(VecScale(Y, 0.5));
    d.slope *= 0.5;
    d.curvature *= 0.25;
    *changed = PETSC_TRUE;
    d.halved = true;
    ++ctx.result.safeguardHalvings;
  }
  PetscFunctionReturn(0);
}

// After every line search (of any type) on the accepted point (line searches that extrapolate, l2 and cp, can leave
// the checked segment). PETSc's bt line search hands over Y already scaled by its length (and resets its length
// afterwards), the others do not: the point is halved towards X in place, W <- (W + X) / 2, which is right for both,
// and the share kept is the direction's postScale.
PetscErrorCode AlphaSafeguard::checkPoint(NewtonContext &ctx, Direction &d, Vec X, Vec W, PetscBool *changed) {
  PetscFunctionBeginUser;
  for (int k = 0; k < kMaxSafeguardHalvings; ++k) {
    bool ok = false;
    PetscCall(acceptable(ctx, W, alphaRef_, &ok));
    if (ok) break;
    PetscCall(VecAXPBY(W, 0.5, 0.5, X));
    d.postScale *= 0.5;
    *changed = PETSC_TRUE;
    d.halved = true;
    ++ctx.result.safeguardHalvings;
  }
  PetscFunctionReturn(0);
}

}  // namespace aries::solver
