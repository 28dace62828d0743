// Anisotropic (fiber) invariants of F with exact gradients and Hessians (paper Sec. 3, App. A.3, A.4).
//
// Every invariant is written for a symmetric "fiber tensor" D in the material frame (Cols x Cols):
//   D = A = a a^T                 -> the single-fiber invariants IV_C(a), V_C(a), I_8(a), VI_C(a)
//   D = (a b^T + b a^T) / 2       -> their cross-fiber versions (App. A.4: A is simply replaced by D)
// so one implementation serves both. With C = F^T F:
//   IV_C(D) = tr(C D)   (= I5 = |Fa|^2 for D = aa^T, = I7(a,b) = a^T C b for the cross tensor)
//   V_C(D)  = tr(C^2 D)
//   I_8(D)  = J tr(D)             (square F only)
//   VI_C(D) = III_C tr(D)         (R x 2 F)
#pragma once

#include "kernels/cauchy_green_invariants.hpp"

namespace aries::kernels {

template <int C>
inline Mat<C, C> fiberTensor(const Vec<C> &a) {
  return a * a.transpose();
}
template <int C>
inline Mat<C, C> crossFiberTensor(const Vec<C> &a, const Vec<C> &b) {
  return 0.5 * (a * b.transpose() + b * a.transpose());
}

// IV_C(D) = tr(F^T F D): gradient 2 F D (Eq. 140); Hessian 2 d_ik D_jl.
template <int R, int C>
inline Derivs<R * C> invariantIVC(const Mat<R, C> &F, const Mat<C, C> &D, Order order = Order::Hessian) {
  constexpr int N = R * C;
  const Mat<R, C> FD = F * D;
  Derivs<N> d;
  d.value = F.cwiseProduct(FD).sum();
  if (wants(order, Order::Gradient)) d.grad = 2.0 * flatten<R, C>(FD);
  if (wants(order, Order::Hessian))
    for (int i = 0; i < R; ++i)
      for (int j = 0; j < C; ++j)
        for (int l = 0; l < C; ++l) d.hess(i * C + j, i * C + l) = 2.0 * D(j, l);
  return d;
}

// V_C(D) = tr(C^2 D): gradient 2 F (C D + D C) (Eq. 141); Hessian (Eq. 142) with M = CD + DC:
//   2 d_ik M_lj + 2 [F_il (FD)_kj + (FF^T)_ik D_lj + (FD)_il F_kj + (F D F^T)_ik d_jl].
template <int R, int C>
inline Derivs<R * C> invariantVC(const Mat<R, C> &F, const Mat<C, C> &D, Order order = Order::Hessian) {
  constexpr int N = R * C;
  const Mat<C, C> Cg = F.transpose() * F;
  const Mat<C, C> M = Cg * D + D * Cg;
  Derivs<N> d;
  d.value = (Cg * Cg).cwiseProduct(D).sum();
  if (wants(order, Order::Gradient)) d.grad = 2.0 * flatten<R, C>(F * M);
  if (wants(order, Order::Hessian)) {
    const Mat<R, C> FD = F * D;
    const Mat<R, R> B = F * F.transpose();
    const Mat<R, R> FDFt = FD * F.transpose();
    for (int i = 0; i < R; ++i)
      for (int j = 0; j < C; ++j)
        for (int k = 0; k < R; ++k)
          for (int l = 0; l < C; ++l) {
            double h = F(i, l) * FD(k, j) + B(i, k) * D(l, j) + FD(i, l) * F(k, j);
            if (i == k) h += M(l, j);
            if (j == l) h += FDFt(i, k);
            d.hess(i * C + j, k * C + l) = 2.0 * h;
          }
  }
  return d;
}

// I_8(D) = J tr(D) (Eq. 143), square F.
template <int R>
inline Derivs<R * R> invariantI8(const Mat<R, R> &F, const Mat<R, R> &D, Order order = Order::Hessian) {
  return invariantJ(F, order).scale(D.trace());
}

// VI_C(D) = III_C tr(D) (Eq. 144), R x 2 F.
template <int R>
inline Derivs<R * 2> invariantVIC(const Mat<R, 2> &F, const Mat<2, 2> &D, Order order = Order::Hessian) {
  return invariantIIIC<R>(F, order).scale(D.trace());
}

// I5(a) = |F a|^2 = IV_C(a a^T) (Eq. 11).
template <int R, int C>
inline Derivs<R * C> invariantI5(const Mat<R, C> &F, const Vec<C> &a, Order order = Order::Hessian) {
  return invariantIVC<R, C>(F, fiberTensor<C>(a), order);
}

// I7(a, b) = a^T F^T F b = IV_C((ab^T + ba^T)/2) (Sec. 5.2, Kim 2020's shear invariant).
template <int R, int C>
inline Derivs<R * C> invariantI7(const Mat<R, C> &F, const Vec<C> &a, const Vec<C> &b, Order order = Order::Hessian) {
  return invariantIVC<R, C>(F, crossFiberTensor<C>(a, b), order);
}

}  // namespace aries::kernels
