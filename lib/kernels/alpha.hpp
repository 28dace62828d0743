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

template <int R, int C>
inline Derivs<R * C> alphaMeasure(const Mat<R, C> &F, Order order = Order::Hessian) {
  return alphaMeasure(makeRootContext<R, C>(F, order));
}

}  // namespace aries::kernels
