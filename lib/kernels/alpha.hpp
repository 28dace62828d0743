// The singularity measure alpha with PK1 and Hessian (paper Eqs. 27-30, App. B):
//   3x3: alpha = 4 f^3 - 4 I_C f - 8 J = 8 (s1+s2)(s1+s3)(s2+s3)        (Eqs. 27-28, 145-146)
//   2x2: alpha = f = s1 + s2                                            (Eqs. 29, 147-148)
//   3x2: alpha = f sqrt(III_C) = (s1 + s2) s1 s2                          (Eqs. 30, 149-150)
// (Eq. 30 prints (s1 + s2) sqrt(s1 s2), but sqrt(III_C) = sqrt(det C) = s1 s2: cloth alpha scales like |F|^3.)
// alpha >= 0 always; alpha = 0 exactly on the singular set of I4 (inverted-to-mirror, collapsed). The value comes
// from root_function.hpp (product of eigenvalue gaps near the singular set, so it never comes out negative).
#pragma once

#include "kernels/rotation.hpp"

namespace aries::kernels {

inline Derivs<9> alphaMeasure(const RootContext<3, 3> &ctx) {
  Derivs<9> out;
  out.value = ctx.rd.root.alpha;
  if (!wants(ctx.order, Order::Gradient)) return out;
  const Mat<3, 3> &F = ctx.F;
  const double f = ctx.rd.root.f, IC = ctx.y.y[0].value;
  const Derivs<9> I1 = invariantI1(ctx);
  const Derivs<9> &J = ctx.y.y[2];
  const Vec<9> fF = flatten<3, 3>(F);
  const Vec<9> &r = I1.grad;
  out.grad = 4.0 * ((3.0 * f * f - IC) * r - 2.0 * f * fF - 2.0 * J.grad);  // Eq. 145
  if (!wants(ctx.order, Order::Hessian)) return out;
  out.hess = 4.0 * (6.0 * f * r * r.transpose() + (3.0 * f * f - IC) * I1.hess -
                    2.0 * (r * fF.transpose() + fF * r.transpose()) - 2.0 * f * Mat<9, 9>::Identity() -
                    2.0 * J.hess);  // Eq. 146
  return out;
}

inline Derivs<4> alphaMeasure(const RootContext<2, 2> &ctx) { return invariantI1(ctx); }  // Eqs. 147-148

inline Derivs<6> alphaMeasure(const RootContext<3, 2> &ctx) {
  Derivs<6> out;
  out.value = ctx.rd.root.alpha;
  if (!wants(ctx.order, Order::Gradient)) return out;
  out = product<6>(invariantI1(ctx), invariantI3(ctx.F, ctx.order), ctx.order);  // Eqs. 149-150
  out.value = ctx.rd.root.alpha;
  return out;
}

// The scale-free measure (aries, not in the paper): alpha (I_C / C)^(-k/2), k = alpha's degree in F (3 for 3x3 and
// 3x2, 1 for 2x2), i.e. alpha of F / s with s^2 = I_C / C the mean squared stretch. It equals alpha wherever I_C = C
// (at rest and near it) and does not change when F is scaled, so a band [eps, 3 eps] in it is the same relative
// distance to the singular set at every stretch; in alpha itself (~ s^3 in 3D) the band of a cell stretched by s is s^3
// times thinner in relative terms, and there I4's derivatives (~ 1/alpha) are largest.
template <int R, int C>
inline constexpr int alphaDegree = (R == 2 && C == 2) ? 1 : 3;

template <int R, int C>
inline double scaleFreeFactor(const Mat<R, C> &F) {
  return std::pow(F.squaredNorm() / C, -0.5 * alphaDegree<R, C>);
}

// The scale-free measure with its derivatives from alpha's (value, gradient, Hessian at F as `order` asks).
template <int R, int C>
inline Derivs<R * C> scaleFreeAlpha(const Mat<R, C> &F, const Derivs<R * C> &alpha, Order order) {
  constexpr int N = R * C;
  const double p = -0.5 * alphaDegree<R, C>, u = F.squaredNorm() / C;
  Derivs<N> h;  // (I_C / C)^p
  h.value = scaleFreeFactor<R, C>(F);
  if (wants(order, Order::Gradient)) {
    const Vec<N> du = (2.0 / C) * flatten<R, C>(F);
    const double d1 = p * std::pow(u, p - 1.0);
    h.grad = d1 * du;
    if (wants(order, Order::Hessian))
      h.hess = p * (p - 1.0) * std::pow(u, p - 2.0) * du * du.transpose() + (2.0 / C) * d1 * Mat<N, N>::Identity();
  }
  return product<N>(alpha, h, order);
}

template <int R, int C>
inline Derivs<R * C> alphaMeasure(const Mat<R, C> &F, Order order = Order::Hessian) {
  return alphaMeasure(makeRootContext<R, C>(F, order));
}

}  // namespace aries::kernels
