// Low-order cloth energies built on I4 / I6 (paper Sec. 5.2):
//   bw46  = mu1/2 (I2 - 2 I1 + 2)                                            (Eq. 49, isotropic)
//   bw461 = mu1/2 [(I4(a) - 1)^2 + (I4(b) - 1)^2] + mu2 I6(a,b)^2             (Eq. 52, orthonormal a, b)
//   bw46s = mu1/2 [(I4(a) - 1)^2 + (I4(b) - 1)^2] + mu2 (I6(a,b) - a^T b)^2   (Eq. 53, non-orthogonal fibers)
// Eq. 53's stretch part mu1/2 (I4a^2 + I4b^2 - 2(I4a + I4b - 1)) is written in its equal squared form. With
// orthonormal fibers and mu2 = mu1, bw461 == bw46 (App. D identity, tested).
#pragma once

#include "energies/iarap_lin.hpp"
#include "energies/singularity.hpp"

namespace aries::energies {

template <int R, int C>
inline kernels::Derivs<R * C> decoupledCloth(const StretchTerms<R, C> &terms, const Vec<C> &a, const Vec<C> &b,
                                             double mu1, double mu2, double shearOffset, kernels::Order order) {
  constexpr int N = R * C;
  kernels::Derivs<N> out;
  for (const Vec<C> *fib : {&a, &b}) {
    const kernels::Derivs<N> I4 = terms(kernels::fiberTensor<C>(*fib));
    const double d = I4.value - 1.0;
    out += kernels::compose<N>(I4, 0.5 * mu1 * d * d, mu1 * d, mu1, order);
  }
  const kernels::Derivs<N> I6 = terms(kernels::crossFiberTensor<C>(a, b));
  const double s = I6.value - shearOffset;
  out += kernels::compose<N>(I6, mu2 * s * s, 2.0 * mu2 * s, 2.0 * mu2, order);
  return out;
}

}  // namespace aries::energies
