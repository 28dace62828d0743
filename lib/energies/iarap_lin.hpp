// Isotropic ARAP in the direct low-order form of Lin et al. 2022 (Eq. 40): mu (I2 - 2 I1 + d) = mu |F - R|^2.
// Its PK1 2 mu (F - R) is bounded everywhere (App. C); the Hessian's dR/dF part is what PSD projection clamps.
#pragma once

#include "energies/material.hpp"

namespace aries::energies {

template <int R, int C>
inline kernels::Derivs<R * C> iarapLinShear(const kernels::RootContext<R, C> &ctx, double mu) {
  kernels::Derivs<R * C> out = kernels::invariantIC<R, C>(ctx.F, ctx.order);
  out += kernels::invariantI1(ctx).scale(-2.0);
  out.value += C;
  return out.scale(mu);
}

}  // namespace aries::energies
