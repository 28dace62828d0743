// Volume term lambda/2 (J - J0)^2 for square F (J0 = 1, or det S_t for shape targeting, Eq. 54).
#pragma once

#include "energies/material.hpp"

namespace aries::energies {

template <int D>
inline const kernels::Derivs<D * D> &jacobianOf(const kernels::RootContext<D, D> &ctx) {
  return ctx.y.y[kernels::RootSpace<D, D>::K - 1];  // J is the last root invariant for square F
}

template <int N>
inline kernels::Derivs<N> volumeTerm(const kernels::Derivs<N> &J, double lambda, double J0, kernels::Order order) {
  const double d = J.value - J0;
  return kernels::compose<N>(J, 0.5 * lambda * d * d, lambda * d, lambda, order);
}

}  // namespace aries::energies
