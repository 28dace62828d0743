// The isotropic Cauchy-Green invariants of F (paper Sec. 3, Eq. 13) with exact gradients and Hessians:
//   I_C = tr C = |F|^2,  II_C = |C|^2 = tr(C^2),  J = det F (square F),  III_C = det C,
// where C = F^T F. These feed the root function f (Eq. 14) and every energy's chain rule (Eq. 19).
#pragma once

#include "kernels/types.hpp"

namespace aries::kernels {

// I_C = |F|_F^2: gradient 2F, Hessian 2 Id.
template <int R, int C>
inline Derivs<R * C> invariantIC(const Mat<R, C> &F, Order order = Order::Hessian) {
  constexpr int N = R * C;
  Derivs<N> d;
  d.value = F.squaredNorm();
  if (wants(order, Order::Gradient)) d.grad = 2.0 * flatten<R, C>(F);
  if (wants(order, Order::Hessian)) d.hess = 2.0 * Mat<N, N>::Identity();
  return d;
}

// Adds c * d2 II_C / dF2 to H: entries 4 c (d_ik C_lj + F_il F_kj + (F F^T)_ik d_jl), C = F^T F.
template <int R, int C>
inline void addHessianIIC(const Mat<R, C> &F, const Mat<C, C> &Cg, double c, Mat<R * C, R * C> &H) {
  const Mat<R, R> B = F * F.transpose();
  const double c4 = 4.0 * c;
  for (int i = 0; i < R; ++i)
    for (int j = 0; j < C; ++j)
      for (int k = 0; k < R; ++k)
        for (int l = 0; l < C; ++l) {
          double h = F(i, l) * F(k, j);
          if (i == k) h += Cg(l, j);
          if (j == l) h += B(i, k);
          H(i * C + j, k * C + l) += c4 * h;
        }
}

// II_C = |F^T F|^2: gradient 4 F C; Hessian see addHessianIIC.
template <int R, int C>
inline Derivs<R * C> invariantIIC(const Mat<R, C> &F, Order order = Order::Hessian) {
  const Mat<C, C> Cg = F.transpose() * F;
  Derivs<R * C> d;
  d.value = Cg.squaredNorm();
  if (wants(order, Order::Gradient)) d.grad = 4.0 * flatten<R, C>(F * Cg);
  if (wants(order, Order::Hessian)) addHessianIIC<R, C>(F, Cg, 1.0, d.hess);
  return d;
}

// Cofactor matrix of a square F (dJ/dF).
inline Mat<3, 3> cofactor(const Mat<3, 3> &F) {
  Mat<3, 3> c;
  c << F(1, 1) * F(2, 2) - F(1, 2) * F(2, 1), F(1, 2) * F(2, 0) - F(1, 0) * F(2, 2),
      F(1, 0) * F(2, 1) - F(1, 1) * F(2, 0), F(0, 2) * F(2, 1) - F(0, 1) * F(2, 2),
      F(0, 0) * F(2, 2) - F(0, 2) * F(2, 0), F(0, 1) * F(2, 0) - F(0, 0) * F(2, 1),
      F(0, 1) * F(1, 2) - F(0, 2) * F(1, 1), F(0, 2) * F(1, 0) - F(0, 0) * F(1, 2),
      F(0, 0) * F(1, 1) - F(0, 1) * F(1, 0);
  return c;
}
inline Mat<2, 2> cofactor(const Mat<2, 2> &F) {
  Mat<2, 2> c;
  c << F(1, 1), -F(1, 0), -F(0, 1), F(0, 0);
  return c;
}

// Adds c * d2 J / dF2 to H for 3x3 F: d2J/dF_ij dF_km = sum_ln eps_ikl eps_jmn F_ln (block (i,k) is the signed
// cross-product matrix of row l of F, l the third index).
inline void addHessianJ(const Mat<3, 3> &F, double c, Mat<9, 9> &H) {
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) {
      if (i == k) continue;
      const int l = 3 - i - k;
      const double s = ((k - i + 3) % 3 == 1) ? c : -c;  // c * eps_ikl
      const double a0 = s * F(l, 0), a1 = s * F(l, 1), a2 = s * F(l, 2);
      const int r = i * 3, q = k * 3;
      H(r, q + 1) += a2;
      H(r, q + 2) -= a1;
      H(r + 1, q) -= a2;
      H(r + 1, q + 2) += a0;
      H(r + 2, q) += a1;
      H(r + 2, q + 1) -= a0;
    }
}

// J = det F for square F, gradient cof F.
inline Derivs<9> invariantJ(const Mat<3, 3> &F, Order order = Order::Hessian) {
  Derivs<9> d;
  d.value = F.determinant();
  if (wants(order, Order::Gradient)) d.grad = flatten<3, 3>(cofactor(F));
  if (wants(order, Order::Hessian)) addHessianJ(F, 1.0, d.hess);
  return d;
}

inline Derivs<4> invariantJ(const Mat<2, 2> &F, Order order = Order::Hessian) {
  Derivs<4> d;
  d.value = F(0, 0) * F(1, 1) - F(0, 1) * F(1, 0);
  if (wants(order, Order::Gradient)) d.grad = flatten<2, 2>(cofactor(F));
  if (wants(order, Order::Hessian)) {
    d.hess(0, 3) = d.hess(3, 0) = 1.0;
    d.hess(1, 2) = d.hess(2, 1) = -1.0;
  }
  return d;
}

// III_C = det(F^T F) for an R x 2 matrix (cloth and planar triangles). Computed as |f0 x f1|^2 (3x2) or J^2 (2x2),
// both free of cancellation. With adj(C) = tr(C) I - C (2x2):
//   gradient 2 F adj(C);  Hessian 2 d_ik adj(C)_lj + 4 F_ij F_kl - 2 F_il F_kj - 2 (F F^T)_ik d_jl.
template <int R>
inline Derivs<R * 2> invariantIIIC(const Mat<R, 2> &F, Order order = Order::Hessian) {
  constexpr int N = R * 2;
  const Mat<2, 2> Cg = F.transpose() * F;
  Derivs<N> d;
  if constexpr (R == 3) {
    const Eigen::Vector3d c0 = F.col(0), c1 = F.col(1);
    d.value = c0.cross(c1).squaredNorm();
  } else {
    const double J = F(0, 0) * F(1, 1) - F(0, 1) * F(1, 0);
    d.value = J * J;
  }
  if (!wants(order, Order::Gradient)) return d;
  Mat<2, 2> adjC;
  adjC << Cg(1, 1), -Cg(0, 1), -Cg(1, 0), Cg(0, 0);
  d.grad = 2.0 * flatten<R, 2>(F * adjC);
  if (!wants(order, Order::Hessian)) return d;
  const Mat<R, R> B = F * F.transpose();
  for (int i = 0; i < R; ++i)
    for (int j = 0; j < 2; ++j)
      for (int k = 0; k < R; ++k)
        for (int l = 0; l < 2; ++l) {
          double h = 4.0 * F(i, j) * F(k, l) - 2.0 * F(i, l) * F(k, j);
          if (i == k) h += 2.0 * adjC(l, j);
          if (j == l) h -= 2.0 * B(i, k);
          d.hess(i * 2 + j, k * 2 + l) = h;
        }
  return d;
}

}  // namespace aries::kernels
