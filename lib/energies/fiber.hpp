// Fiber stiffening term gamma/2 (I4(a) - 1)^2 (paper Sec. 6, octopus), added to iarap by the `fiber` energy.
#pragma once

#include "energies/singularity.hpp"

namespace aries::energies {

template <int R, int C>
inline kernels::Derivs<R * C> fiberStiffening(const StretchTerms<R, C> &terms, const Vec<C> &a, double gamma,
                                              kernels::Order order) {
  const kernels::Derivs<R * C> I4 = terms(kernels::fiberTensor<C>(a));
  const double d = I4.value - 1.0;
  return kernels::compose<R * C>(I4, 0.5 * gamma * d * d, gamma * d, gamma, order);
}

}  // namespace aries::energies
