// Singularity fix 2: the aberration barrier (paper Sec. 4.2, Eq. 34)
//   b(alpha) = -(alpha - eps)^2 ln(alpha / eps)   for alpha <= eps,   0 otherwise,   eps = 1e-2,
// added to an element's energy. b, b', b'' all vanish at alpha = eps, so the energy stays C2; b -> +inf as
// alpha -> 0+. At alpha <= 0 (exactly singular, e.g. an inside-out start) b is undefined: the value is +inf and the
// derivatives are left zero, so a line search rejects such a state and a caller can fall back to the mollifier
// (the paper's advice, Sec. 7.1).
#pragma once

#include "kernels/alpha.hpp"

namespace aries::kernels {

struct BarrierParams {
  double eps = 1e-2;
};

struct BarrierProfile {
  double value, d1, d2;
};

inline BarrierProfile barrierProfile(double alpha, double eps) {
  if (alpha >= eps) return {0.0, 0.0, 0.0};
  if (!(alpha > 0.0)) return {std::numeric_limits<double>::infinity(), 0.0, 0.0};
  const double d = alpha - eps, L = std::log(alpha / eps);
  return {-d * d * L, -2.0 * d * L - d * d / alpha, -2.0 * L - 4.0 * d / alpha + d * d / (alpha * alpha)};
}

// b(alpha(F)) with derivatives; `alpha` must be alphaMeasure at the same F.
template <int N>
inline Derivs<N> aberrationBarrier(const Derivs<N> &alpha, const BarrierParams &p, Order order) {
  const BarrierProfile b = barrierProfile(alpha.value, p.eps);
  if (b.d1 == 0.0 && b.d2 == 0.0) {
    Derivs<N> out;
    out.value = b.value;
    return out;
  }
  return compose<N>(alpha, b.value, b.d1, b.d2, order);
}

template <int R, int C>
inline Derivs<R * C> aberrationBarrier(const Mat<R, C> &F, const BarrierParams &p = {}, Order order = Order::Hessian) {
  const auto ctx = makeRootContext<R, C>(F, order);
  return aberrationBarrier<R * C>(alphaMeasure(ctx), p, order);
}

}  // namespace aries::kernels
