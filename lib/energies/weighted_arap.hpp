// Layered anisotropic ARAP (paper Sec. 5.1): the sum of direction terms
//   sum_k c_k |(F - R) u_k|^2 = IV_C(W) - 2 tr(S W) + tr(W),    W = sum_k c_k u_k u_k^T,
// i.e. Eq. 38 per direction (|(F-R)a|^2 = I5 - 2 I4 + 1) summed as in Eqs. 39-41. Every quantity in Eqs. 17 and
// 140-144 is linear in the fiber tensor, so the sum of the direction terms is evaluated as one tensor term (Eq. 42
// in tensor form); the mollified terms share t(alpha), so this holds for every singularity mode.
//   alx:   W = (mu/2) a a^T          iarap: W = mu I          ortho: W = sum mu_k u_k u_k^T   aniso: sum c_k d_k d_k^T
#pragma once

#include "energies/singularity.hpp"

namespace aries::energies {

template <int R, int C>
inline kernels::Derivs<R * C> weightedArap(const kernels::RootContext<R, C> &ctx, const StretchTerms<R, C> &terms,
                                           const Mat<C, C> &W) {
  kernels::Derivs<R * C> out = kernels::invariantIVC<R, C>(ctx.F, W, ctx.order);
  kernels::Derivs<R * C> s = terms(W);
  out += s.scale(-2.0);
  out.value += W.trace();
  return out;
}

}  // namespace aries::energies
