// Shape targeting (paper Sec. 5.3, Eq. 65) with its volume term (Eq. 54):
//   Psi_ST = mu/2 [ (I2 - 2 I1 + d) + sum_i 2 (1 - lambda_i) I4(v_i) + |S_t|^2 - d ] + lambda/2 (J - det S_t)^2
// for the symmetric target S_t = sum_i lambda_i v_i v_i^T. The I4 terms are summed as one tensor term,
// sum_i (1 - lambda_i) I4(v_i) = tr(S (I - S_t)) (linear in the fiber tensor), so no per-element eigendecomposition
// is needed; they carry the singularity mode, the iARAP part (Lin 2022) is singularity-free (App. C).
// Equals mu/2 |F - R S_t|^2 + lambda/2 (J - det S_t)^2 (tested against an SVD).
#pragma once

#include "energies/iarap_lin.hpp"
#include "energies/singularity.hpp"

namespace aries::energies {

template <int R, int C>
inline kernels::Derivs<R * C> shapeTargetShear(const kernels::RootContext<R, C> &ctx, const StretchTerms<R, C> &terms,
                                               const Mat<C, C> &St, double mu) {
  kernels::Derivs<R * C> out = iarapLinShear<R, C>(ctx, 0.5 * mu);
  const Mat<C, C> D = Mat<C, C>::Identity() - St;
  out += terms(D).scale(mu);
  out.value += 0.5 * mu * (St.squaredNorm() - C);
  return out;
}

}  // namespace aries::energies
