// Singularity fix 1: the smooth mollifier (paper Sec. 4.2, Eqs. 31-33).
//   S2(x) = 6x^5 - 15x^4 + 10x^3 on [0,1] (0 below, 1 above)               (Eq. 31, smootherstep)
//   t(alpha) = S2((alpha - eps) / (2 eps))
//   I^ = g                           alpha < eps
//        (1 - t) g + t I             eps <= alpha <= 3 eps                  (Eqs. 32-33)
//        I                           alpha > 3 eps
// with the proxy g = c constant (default 0, the paper's choice) and eps = 1e-3. S2' = S2'' = 0 at both blend ends,
// so I^ is C2 across alpha = eps and 3 eps wherever I is smooth. Applies to I4 and I6 alike. For a general fiber
// tensor D the proxy is c tr(D) (= c for I4 with a unit fiber), which keeps I^ linear in D: the mollified sum of
// direction terms equals the mollified term of the summed tensor (used by weighted_arap.hpp).
#pragma once

#include "kernels/alpha.hpp"
#include "kernels/stretch_invariants.hpp"

namespace aries::kernels {

// What the band [eps, 3 eps] is measured in: alpha (Eq. 28, the paper) or alpha (I_C / C)^(-k/2) (alpha.hpp,
// scaleFreeAlpha: the same at rest, independent of the stretch's scale).
enum class MollifierMeasure { Alpha, ScaleFree };

struct MollifierParams {
  double eps = 1e-3;    // threshold in the measure's coordinate (Eq. 33; -mollifier_eps)
  double proxy = 0.0;   // g(F) = c (Eq. 33)
  MollifierMeasure measure = MollifierMeasure::Alpha;
};

// Whether a coordinate (mollifierCoordinate) lies in the blend band [eps, 3 eps] of Eq. 33; `edge` > 1 widens its top
// (the console's count of cells held at the band, fem/diagnostics.cpp).
inline bool inMollifierBand(double coordinate, const MollifierParams &p, double edge = 1.0) {
  return coordinate >= p.eps && coordinate <= edge * 3.0 * p.eps;
}
// Above the band: Eq. 33 is the raw invariant there.
inline bool aboveMollifierBand(double coordinate, const MollifierParams &p) { return coordinate > 3.0 * p.eps; }

// The band's coordinate at F from alpha's value there (no derivatives).
template <int R, int C>
inline double mollifierCoordinate(const Mat<R, C> &F, double alpha, const MollifierParams &p) {
  return p.measure == MollifierMeasure::ScaleFree ? alpha * scaleFreeFactor<R, C>(F) : alpha;
}

// The band's coordinate with the derivatives the context's order asks for (read inside the band only).
template <int R, int C>
inline Derivs<R * C> mollifierCoordinate(const RootContext<R, C> &ctx, const MollifierParams &p) {
  const Derivs<R * C> alpha = alphaMeasure(ctx);
  return p.measure == MollifierMeasure::ScaleFree ? scaleFreeAlpha<R, C>(ctx.F, alpha, ctx.order) : alpha;
}

// S2 and its first two derivatives (Eq. 31).
struct Smootherstep {
  double value, d1, d2;
};
constexpr Smootherstep smootherstep(double x) {
  if (x <= 0.0) return {0.0, 0.0, 0.0};
  if (x >= 1.0) return {1.0, 0.0, 0.0};
  return {x * x * x * (x * (6.0 * x - 15.0) + 10.0), 30.0 * x * x * (x - 1.0) * (x - 1.0),
          60.0 * x * (2.0 * x - 1.0) * (x - 1.0)};
}

// Blend weight t(alpha) with dt/dalpha, d2t/dalpha2.
constexpr Smootherstep mollifierBlend(double alpha, double eps) {
  const Smootherstep s = smootherstep((alpha - eps) / (2.0 * eps));
  return {s.value, s.d1 / (2.0 * eps), s.d2 / (4.0 * eps * eps)};
}

// Mollified tr(S D) (Eq. 33). `alpha` must be mollifierCoordinate(ctx, p) (passed in so several terms share it); its
// derivatives are only read inside the blend band, and the raw invariant is not evaluated below eps, where its
// derivatives are unbounded.
template <int R, int C>
inline Derivs<R * C> mollifiedStretch(const RootContext<R, C> &ctx, const Mat<C, C> &D, const Derivs<R * C> &alpha,
                                      const MollifierParams &p) {
  constexpr int N = R * C;
  const double a = alpha.value;
  Derivs<N> out;
  const double g = p.proxy * D.trace();
  if (!(a >= p.eps)) {  // also catches NaN alpha: the proxy is the safe answer
    out.value = g;
    return out;
  }
  Derivs<N> I = stretchInvariant<R, C>(ctx, D);
  if (aboveMollifierBand(a, p)) return I;
  const Smootherstep t = mollifierBlend(a, p.eps);
  const double diff = I.value - g;
  out.value = g + t.value * diff;
  if (wants(ctx.order, Order::Gradient)) out.grad = t.d1 * diff * alpha.grad + t.value * I.grad;
  if (wants(ctx.order, Order::Hessian))
    out.hess = t.d2 * diff * alpha.grad * alpha.grad.transpose() +
               t.d1 * (alpha.grad * I.grad.transpose() + I.grad * alpha.grad.transpose()) + t.d1 * diff * alpha.hess +
               t.value * I.hess;
  return out;
}

template <int R, int C>
inline Derivs<R * C> mollifiedI4(const Mat<R, C> &F, const Vec<C> &a, const MollifierParams &p = {},
                                 Order order = Order::Hessian) {
  const auto ctx = makeRootContext<R, C>(F, order);
  return mollifiedStretch<R, C>(ctx, fiberTensor<C>(a), mollifierCoordinate(ctx, p), p);
}

template <int R, int C>
inline Derivs<R * C> mollifiedI6(const Mat<R, C> &F, const Vec<C> &a, const Vec<C> &b, const MollifierParams &p = {},
                                 Order order = Order::Hessian) {
  const auto ctx = makeRootContext<R, C>(F, order);
  return mollifiedStretch<R, C>(ctx, crossFiberTensor<C>(a, b), mollifierCoordinate(ctx, p), p);
}

}  // namespace aries::kernels
