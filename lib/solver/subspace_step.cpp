// 3. SubspaceStep (newton_steps.hpp, -newton_subspace m, -newton_subspace_max): the update minimizes the true
// quadratic model (exact Hessian) over span{Newton direction, last m updates}, a Newton-preconditioned nonlinear-CG /
// SESOP step. Filtering makes the model of inverted and compressed elements stiffer than they are, so plain projected
// Newton converges linearly with steps that are too short; the exact curvature in a small subspace restores the step
// length and direction. Where the exact curvature along the Newton direction is negative (the energy is not convex
// along it: a snap-through, a saddle), no subspace step is taken and the filtered model's step is far too short: the
// full step is doubled while the energy falls (-newton_extrapolate).
#include "solver/newton_steps.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>

namespace aries::solver {

namespace {
// The subspace step needs its (scaled) Gram matrix this well conditioned (smallest / largest eigenvalue).
constexpr double kSubspaceConditioning = 1e-8;
// A limited subspace step must decrease the energy by this share of its slope at full length (Armijo).
constexpr double kSubspaceArmijo = 1e-4;
}  // namespace

SubspaceStep::~SubspaceStep() {
  for (Vec *v : {&prevX_, &newtonDir_})
    if (*v) VecDestroy(v);
  for (Vec &v : updates_) VecDestroy(&v);
}

PetscErrorCode SubspaceStep::beginSolve(NewtonContext &ctx) {
  PetscFunctionBeginUser;
  if (!prevX_) {
    PetscCall(VecDuplicate(ctx.work, &prevX_));
    PetscCall(VecDuplicate(ctx.work, &newtonDir_));
    updates_.resize(opts_.size);
    for (Vec &v : updates_) PetscCall(VecDuplicate(ctx.work, &v));
  }
  count_ = 0;
  lastFull_ = false;
  PetscFunctionReturn(0);
}

// Minimize the true quadratic model m(u) = -g.u... over u = -(c_0 Y + sum_j c_j D_j), D_j = -s_j the previous
// updates s_j (newest first): G c = r with G_kl = D_k^T H D_l (exact Hessian) and r_k = g . D_k. The largest leading
// block of G that is positive definite is used; the step must keep a positive Newton coefficient c_0.
PetscErrorCode SubspaceStep::shapeDirection(NewtonContext &ctx, Direction &d, Vec X, Vec Y, Vec F,
                                            PetscBool *changed) {
  PetscFunctionBeginUser;
  if (ctx.result.history.empty()) {  // first direction of the solve: nothing to combine with yet
    PetscCall(VecCopy(X, prevX_));
    PetscFunctionReturn(0);
  }
  // newest update first
  Vec oldest = updates_.back();
  for (size_t j = updates_.size() - 1; j > 0; --j) updates_[j] = updates_[j - 1];
  updates_[0] = oldest;
  PetscCall(VecWAXPY(updates_[0], -1.0, prevX_, X));
  PetscCall(VecCopy(X, prevX_));
  count_ = std::min<PetscInt>(count_ + 1, opts_.size);
  // A limited subspace step (static solves) is taken only after an update the line search accepted in full.
  const bool limited = opts_.maxCoefficient > 0.0;
  if (limited && !lastFull_) PetscFunctionReturn(0);

  const int K = 1 + static_cast<int>(count_);
  std::vector<Vec> dirs(K);
  dirs[0] = Y;
  for (int k = 1; k < K; ++k) dirs[k] = updates_[k - 1];
  std::vector<double> G;
  PetscCall(ctx.gram(X, dirs, &G));
  Eigen::VectorXd r(K);
  Eigen::MatrixXd A(K, K);
  r[0] = d.slope;
  for (int k = 1; k < K; ++k) {
    PetscScalar gs;
    PetscCall(VecDot(F, updates_[k - 1], &gs));
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
  if (use < 2) {
    if (A(0, 0) < 0.0 && r[0] > 0.0 && opts_.extrapolate > 0 && lastFull_)
      PetscCall(extrapolate(ctx, d, X, Y, changed));
    PetscFunctionReturn(0);
  }
  if (limited && c[0] > opts_.maxCoefficient) c *= opts_.maxCoefficient / c[0];
  PetscCall(VecCopy(Y, newtonDir_));
  PetscCall(VecScale(Y, c[0]));
  for (int k = 1; k < use; ++k) PetscCall(VecAXPY(Y, -c[k], updates_[k - 1]));
  PetscScalar slope;
  PetscCall(VecDot(F, Y, &slope));
  if (limited) {
    // A limited subspace step must decrease the energy at full length; otherwise the Newton direction goes to the
    // line search unchanged.
    PetscReal eNew;
    PetscCall(VecWAXPY(ctx.work, -1.0, Y, X));
    PetscCall(ctx.energyAt(ctx.work, &eNew, nullptr));
    if (!(eNew <= d.energyBefore - kSubspaceArmijo * slope)) {
      PetscCall(VecCopy(newtonDir_, Y));
      PetscFunctionReturn(0);
    }
  }
  d.slope = slope;
  // curvature of the combined step for the adaptive filter's ratio: c^T A c
  d.curvature = c.dot(A.topLeftCorner(use, use) * c);
  d.haveCurvature = true;
  d.record.accelerated = true;
  *changed = PETSC_TRUE;
  PetscFunctionReturn(0);
}

// Negative exact curvature along Y (a descent direction) after a full update: the energy along X - t Y falls faster
// than the filtered model says, and plain projected Newton creeps along it with full steps of about the same length,
// one update each (measured: the Fig. 13 interaction on the 7.4k-hex bunny, step 182: 14 such updates of 2.5e-4 in a
// row). The step is doubled, up to opts_.extrapolate times, while each doubling lowers the energy by at least what the
// full step lowered it (as it does where the curvature is truly negative; a flat stretch, whose decrease round-off
// could decide differently on another partition, stops it) and the alpha safeguard accepts the doubled step; the line
// search and the safeguard then act on the longer step as on any other.
PetscErrorCode SubspaceStep::extrapolate(NewtonContext &ctx, Direction &d, Vec X, Vec Y, PetscBool *changed) {
  PetscReal best, e;
  PetscFunctionBeginUser;
  PetscCall(VecWAXPY(ctx.work, -1.0, Y, X));
  PetscCall(ctx.energyAt(ctx.work, &best, nullptr));
  const double gain = d.energyBefore - best;  // the full step's decrease
  if (!(gain > 0.0)) PetscFunctionReturn(0);
  double scale = 1.0;
  if (safeguard_) PetscCall(safeguard_->alphasAt(ctx, X, &alphaRef_));
  for (PetscInt k = 1; k <= opts_.extrapolate; ++k) {
    PetscCall(VecWAXPY(ctx.work, -2.0 * scale, Y, X));
    bool ok = true;  // a doubling the safeguard would halve again stops here (its halvings would also end the
                     // exact-Hessian iterations as after a shortened step: HessianFilter)
    if (safeguard_) PetscCall(safeguard_->acceptable(ctx, ctx.work, alphaRef_, &ok));
    if (!ok) break;
    PetscCall(ctx.energyAt(ctx.work, &e, nullptr));
    if (!(e <= best - gain)) break;
    best = e;
    scale *= 2.0;
  }
  if (scale == 1.0) PetscFunctionReturn(0);
  PetscCall(VecScale(Y, scale));
  d.slope *= scale;
  d.record.extrapolated = scale;
  *changed = PETSC_TRUE;
  PetscFunctionReturn(0);
}

PetscErrorCode SubspaceStep::finishUpdate(NewtonContext &, const Direction &d, Vec, double lambda) {
  lastFull_ = lambda >= 1.0 && !d.halved;
  return 0;
}

}  // namespace aries::solver
