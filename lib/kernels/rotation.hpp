// The analytic rotation R = df/dF (Eqs. 12, 20, 22) and the low-order isotropic invariants of Smith et al. 2019
// (Eq. 1): I1 = tr S = f, I2 = |S|^2 = I_C, I3 = det S.
//
// R is the signed polar rotation (F = R S with S symmetric, det R = +1 for square F). Evaluation paths:
//   3x3: Eq. 12, R = 2 f_1 F + 4 f_2 F C + f_J cof(F); where the root came from Horn's eigenproblem (alpha_n small,
//        see root_function.hpp) R is built from the top eigenvector of K(F) instead: the same matrix where it is
//        unique, a valid maximizer of tr(R^T F) where it is not (alpha = 0, e.g. F = -I), and accurate to eps/gap
//        instead of eps/alpha.
//   2x2: Eq. 20, R = (F + cof F) / f, exact (a scaled rotation divided by its norm).
//   3x2: Eq. 22 evaluated in the frame of the column plane: F = E G (thin QR), R = E R_2x2(G). Identical to
//        f_1 2F + f_3 dIII_C/dF, but without the 0/0 that formula has at III_C = 0.
#pragma once

#include "kernels/root_function.hpp"

namespace aries::kernels {

inline Mat<3, 3> rotationFromRoot(const Mat<3, 3> &F, const RootDerivatives<3> &rd) {
  if (rd.root.fromEigen) return quaternionToRotation(rd.root.quaternion);
  const Mat<3, 3> Cg = F.transpose() * F;
  return 2.0 * rd.d1[0] * F + 4.0 * rd.d1[1] * F * Cg + rd.d1[2] * cofactor(F);
}

inline Mat<2, 2> rotationFromRoot(const Mat<2, 2> &F, const RootDerivatives<2> &rd) {
  const double f = rd.root.f;
  if (!(f > 0.0)) return Mat<2, 2>::Identity();
  return (F + cofactor(F)) / f;
}

inline Mat<3, 2> rotationFromRoot(const Mat<3, 2> &F, const RootDerivatives<2> &) {
  Eigen::Vector3d e0 = F.col(0);
  const double n0 = e0.norm();
  if (n0 > 0.0) {
    e0 /= n0;
  } else {
    const Eigen::Vector3d c1 = F.col(1);
    e0 = c1.norm() > 0.0 ? Eigen::Vector3d(c1.unitOrthogonal()) : Eigen::Vector3d::UnitX();
  }
  Eigen::Vector3d e1 = F.col(1) - e0.dot(F.col(1)) * e0;
  e1 = e1.norm() > 0.0 ? Eigen::Vector3d(e1.normalized()) : Eigen::Vector3d(e0.unitOrthogonal());
  Mat<3, 2> E;
  E << e0, e1;
  const Mat<2, 2> G = E.transpose() * F;  // upper triangular, G(1,1) >= 0
  const double f = std::hypot(G(0, 0) + G(1, 1), G(1, 0) - G(0, 1));
  const Mat<2, 2> R2 = f > 0.0 ? Mat<2, 2>((G + cofactor(G)) / f) : Mat<2, 2>::Identity();
  return E * R2;
}

template <int R, int C>
inline Mat<R, C> analyticRotation(const RootContext<R, C> &ctx) {
  return rotationFromRoot(ctx.F, ctx.rd);
}
template <int R, int C>
inline Mat<R, C> analyticRotation(const Mat<R, C> &F) {
  return rotationFromRoot(F, rootDerivatives(F, 1));
}

// I1 = f with gradient R and Hessian dR/dF = sum_k f_k d2y_k/dF2 + sum_kl f_kl dy_k (x) dy_l (Eq. 19). The Hessian
// grows like 1/alpha near the singular set (paper footnote 6).
template <int R, int C>
inline Derivs<R * C> invariantI1(const RootContext<R, C> &ctx) {
  constexpr int K = RootSpace<R, C>::K;
  Derivs<R * C> out;
  out.value = ctx.rd.root.f;
  if (!wants(ctx.order, Order::Gradient)) return out;
  out.grad = flatten<R, C>(analyticRotation(ctx));
  if (!wants(ctx.order, Order::Hessian)) return out;
  Derivs<R * C> chain;
  const Derivs<R * C> *z[K];
  for (int k = 0; k < K; ++k) z[k] = &ctx.y.y[k];
  accumulateChain<R * C, K>(chain, z, ctx.rd.d1, ctx.rd.d2, ctx.order);
  out.hess = chain.hess;
  return out;
}
template <int R, int C>
inline Derivs<R * C> invariantI1(const Mat<R, C> &F, Order order = Order::Hessian) {
  return invariantI1(makeRootContext<R, C>(F, order));
}

// I2 = |S|_F^2 = |F|_F^2 = I_C.
template <int R, int C>
inline Derivs<R * C> invariantI2(const Mat<R, C> &F, Order order = Order::Hessian) {
  return invariantIC<R, C>(F, order);
}

// I3 = det S: J for square F, sqrt(III_C) for cloth (S is PSD there).
inline Derivs<9> invariantI3(const Mat<3, 3> &F, Order order = Order::Hessian) { return invariantJ(F, order); }
inline Derivs<4> invariantI3(const Mat<2, 2> &F, Order order = Order::Hessian) { return invariantJ(F, order); }
inline Derivs<6> invariantI3(const Mat<3, 2> &F, Order order = Order::Hessian) {
  const Derivs<6> III = invariantIIIC<3>(F, order);
  const double s = std::sqrt(III.value);
  return compose<6>(III, s, 0.5 / s, -0.25 / (s * s * s), order);
}

}  // namespace aries::kernels
