// Baraff-Witkin cloth in the FE form of Kim 2020 (paper Eq. 45), the cloth baseline:
//   mu1/2 [(sqrt(I5(a)) - 1)^2 + (sqrt(I5(b)) - 1)^2] + mu2 (I7(a,b) - a^T b)^2
// The shear term is the generalized one the paper gives for non-orthogonal fibers (Sec. 5.2); it is Kim 2020's
// mu2 I7^2 when a is orthogonal to b.
#pragma once

#include "energies/material.hpp"

namespace aries::energies {

template <int R, int C>
inline kernels::Derivs<R * C> baraffWitkin(const Mat<R, C> &F, const Vec<C> &a, const Vec<C> &b, double mu1,
                                           double mu2, kernels::Order order) {
  constexpr int N = R * C;
  kernels::Derivs<N> out;
  for (const Vec<C> *fib : {&a, &b}) {
    const kernels::Derivs<N> I5 = kernels::invariantI5<R, C>(F, *fib, order);
    const double r = std::sqrt(I5.value), d = r - 1.0;
    out += kernels::compose<N>(I5, 0.5 * mu1 * d * d, 0.5 * mu1 * (1.0 - 1.0 / r), 0.25 * mu1 / (r * r * r), order);
  }
  const kernels::Derivs<N> I7 = kernels::invariantI7<R, C>(F, a, b, order);
  const double s = I7.value - a.dot(b);
  out += kernels::compose<N>(I7, mu2 * s * s, 2.0 * mu2 * s, 2.0 * mu2, order);
  return out;
}

}  // namespace aries::energies
