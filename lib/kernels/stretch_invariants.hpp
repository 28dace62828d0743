// The low-order anisotropic invariant I4(a) = a^T S a and the cross-fiber invariant I6(a, b) = a^T S b in proper
// closed form with PK1 and Hessian (paper Eqs. 15-26, 18-19, App. A.1, A.2, A.4), for 3x3, 2x2 and 3x2 F.
//
// With the root invariants y (root_function.hpp) and the paired fiber invariants X of the symmetric fiber tensor D
// (D = aa^T for I4, (ab^T + ba^T)/2 for I6; fiber_invariants.hpp):
//   I(D) = sum_m w_m f_m(y) X_m(D)                          (Eqs. 17, 21, 26; w = (2,4,1), (2,1), (2,2))
//   dI/dy_n = sum_m w_m f_mn X_m,   dI/dX_m = w_m f_m          (Eqs. 67-72, 103-112)
//   d2I/dy_n dy_p = sum_m w_m f_mnp X_m,  d2I/dy_n dX_m = w_m f_mn,  d2I/dX dX = 0   (Eqs. 73-102, 120-132)
// and the F-derivatives follow by the chain rule (Eqs. 18-19).
//
// These are singular where alpha -> 0 (derivatives scale like 1/alpha, 1/alpha^3 in the Hessian); see mollifier.hpp
// and aberration_barrier.hpp for the two fixes. Where the 3x3 root came from Horn's eigenproblem (alpha_n small) the
// value is evaluated as tr(S D) with S = R^T F, which equals Eq. 17 but stays accurate (and finite at alpha = 0).
#pragma once

#include "kernels/fiber_invariants.hpp"
#include "kernels/rotation.hpp"

namespace aries::kernels {

namespace detail {
// Fiber invariants paired with the root invariants, and their weights w_m. I_8 = tr(D) J and VI_C = tr(D) III_C
// reuse the root invariants already in the context.
inline std::array<Derivs<9>, 3> pairedFiberInvariants(const RootContext<3, 3> &ctx, const Mat<3, 3> &D, Order o) {
  Derivs<9> I8 = ctx.y.y[2];
  return {invariantIVC<3, 3>(ctx.F, D, o), invariantVC<3, 3>(ctx.F, D, o), I8.scale(D.trace())};
}
inline std::array<Derivs<4>, 2> pairedFiberInvariants(const RootContext<2, 2> &ctx, const Mat<2, 2> &D, Order o) {
  Derivs<4> I8 = ctx.y.y[1];
  return {invariantIVC<2, 2>(ctx.F, D, o), I8.scale(D.trace())};
}
inline std::array<Derivs<6>, 2> pairedFiberInvariants(const RootContext<3, 2> &ctx, const Mat<2, 2> &D, Order o) {
  Derivs<6> VIC = ctx.y.y[1];
  return {invariantIVC<3, 2>(ctx.F, D, o), VIC.scale(D.trace())};
}
template <int R, int C>
constexpr std::array<double, RootSpace<R, C>::K> pairingWeights() {
  if constexpr (R == 3 && C == 3)
    return {2.0, 4.0, 1.0};
  else if constexpr (R == 2 && C == 2)
    return {2.0, 1.0};
  else
    return {2.0, 2.0};
}
}  // namespace detail

// The value tr(S D) alone (Eq. 17 / 21 / 26; tr(R^T F D) on Horn's path, see the header comment).
template <int R, int C>
inline double stretchInvariantValue(const RootContext<R, C> &ctx, const Mat<C, C> &D,
                                    const std::array<Derivs<R * C>, RootSpace<R, C>::K> &X) {
  if constexpr (R == 3 && C == 3) {
    if (ctx.rd.root.fromEigen) {
      const Mat<3, 3> S = quaternionToRotation(ctx.rd.root.quaternion).transpose() * ctx.F;
      return 0.5 * (S + S.transpose()).cwiseProduct(D).sum();
    }
  }
  constexpr auto w = detail::pairingWeights<R, C>();
  double v = 0.0;
  for (int m = 0; m < RootSpace<R, C>::K; ++m) v += w[m] * ctx.rd.d1[m] * X[m].value;
  return v;
}
template <int R, int C>
inline double stretchInvariantValue(const RootContext<R, C> &ctx, const Mat<C, C> &D) {
  return stretchInvariantValue<R, C>(ctx, D, detail::pairedFiberInvariants(ctx, D, Order::Value));
}

// D = w I (to round-off): then tr(S D) = w tr(S) = w I1 exactly (Eq. 42 with any orthonormal basis).
template <int C>
inline bool isIsotropic(const Mat<C, C> &D) {
  const Mat<C, C> dev = D - (D.trace() / C) * Mat<C, C>::Identity();
  return dev.cwiseAbs().maxCoeff() <= 1e-14 * D.cwiseAbs().maxCoeff();
}

// tr(S D) for the symmetric fiber tensor D, with derivatives. The context carries everything that depends on F
// only, so an energy summing several directions (iarap, ortho, aniso) computes it once.
template <int R, int C>
inline Derivs<R * C> stretchInvariant(const RootContext<R, C> &ctx, const Mat<C, C> &D) {
  constexpr int N = R * C;
  constexpr int K = RootSpace<R, C>::K;
  constexpr auto w = detail::pairingWeights<R, C>();
  const Order order = ctx.order;
  const auto &rd = ctx.rd;
  if (isIsotropic<C>(D)) {  // Eq. 42: the orthonormal sum of I4 terms is I1, no fiber machinery needed
    Derivs<N> I1 = invariantI1(ctx);
    return I1.scale(D.trace() / C);
  }
  const auto X = detail::pairedFiberInvariants(ctx, D, order);
  Derivs<N> out;
  out.value = stretchInvariantValue<R, C>(ctx, D, X);
  if (!wants(order, Order::Gradient)) return out;

  Vec<2 * K> first;
  Mat<2 * K, 2 * K> second = Mat<2 * K, 2 * K>::Zero();
  for (int n = 0; n < K; ++n) {
    double dy = 0.0;
    for (int m = 0; m < K; ++m) dy += w[m] * rd.d2(m, n) * X[m].value;
    first[n] = dy;
    first[K + n] = w[n] * rd.d1[n];
  }
  if (wants(order, Order::Hessian)) {
    for (int n = 0; n < K; ++n)
      for (int p = 0; p < K; ++p) {
        double s = 0.0;
        for (int m = 0; m < K; ++m) s += w[m] * rd.d3[p](m, n) * X[m].value;
        second(n, p) = s;
      }
    for (int n = 0; n < K; ++n)
      for (int m = 0; m < K; ++m) second(n, K + m) = second(K + m, n) = w[m] * rd.d2(m, n);
  }
  const Derivs<N> *z[2 * K];
  for (int k = 0; k < K; ++k) {
    z[k] = &ctx.y.y[k];
    z[K + k] = &X[k];
  }
  accumulateChain<N, 2 * K>(out, z, first, second, order);
  return out;
}

template <int R, int C>
inline Derivs<R * C> stretchInvariant(const Mat<R, C> &F, const Mat<C, C> &D, Order order = Order::Hessian) {
  return stretchInvariant<R, C>(makeRootContext<R, C>(F, order), D);
}

// I4(a) = a^T S a (Eq. 2 in closed form: Eqs. 17, 21, 26).
template <int R, int C>
inline Derivs<R * C> invariantI4(const Mat<R, C> &F, const Vec<C> &a, Order order = Order::Hessian) {
  return stretchInvariant<R, C>(F, fiberTensor<C>(a), order);
}

// I6(a, b) = a^T S b (Sec. 5.2, App. A.4).
template <int R, int C>
inline Derivs<R * C> invariantI6(const Mat<R, C> &F, const Vec<C> &a, const Vec<C> &b, Order order = Order::Hessian) {
  return stretchInvariant<R, C>(F, crossFiberTensor<C>(a, b), order);
}

}  // namespace aries::kernels
