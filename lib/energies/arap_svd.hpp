// SVD-based ARAP, the rotation-variant reference and baseline: mu |F - R|^2 with R = U V^T from a signed SVD.
// PK1 2 mu (F - R); Hessian 2 mu (Id - dR/dF) with dR/dF from the twist modes (svd_polar.hpp).
#pragma once

#include "energies/material.hpp"
#include "kernels/svd_polar.hpp"

namespace aries::energies {

template <int R, int C>
inline kernels::Derivs<R * C> arapSvdShear(const Mat<R, C> &F, double mu, kernels::Order order) {
  constexpr int N = R * C;
  const auto svd = kernels::signedSvd(F);
  const Mat<R, C> Rot = kernels::svdRotation(svd);
  kernels::Derivs<N> out;
  out.value = mu * (F - Rot).squaredNorm();
  if (kernels::wants(order, kernels::Order::Gradient)) out.grad = 2.0 * mu * kernels::flatten<R, C>(F - Rot);
  if (kernels::wants(order, kernels::Order::Hessian))
    out.hess = 2.0 * mu * (Mat<N, N>::Identity() - kernels::svdRotationGradient(svd));
  return out;
}

}  // namespace aries::energies
