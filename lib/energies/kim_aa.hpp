// Kim et al. 2019 inversion-safe anisotropic ARAP (paper Eq. 9), the baseline:
//   Psi_AA(a) = mu/2 (sqrt(I5) - S(I4))^2,   S(I4) = sign(I4),
// with Kim's PK1 mu (1 - S/sqrt(I5)) F A (the delta term of Eq. 10 dropped, as Kim 2019 Eq. 36 proposes) and its
// Hessian mu (1 - S/sqrt(I5)) (Id (x) A) + mu S / I5^(3/2) vec(FA) vec(FA)^T, whose negative part PSD projection
// clamps. The known flaws are kept on purpose: the energy jumps by 2 mu sqrt(I5) where I4 changes sign (Sec. 2.3)
// and the PK1 divides by sqrt(I5).
#pragma once

#include "energies/material.hpp"
#include "kernels/stretch_invariants.hpp"

namespace aries::energies {

inline double kimStep(double I4) { return I4 > 0.0 ? 1.0 : (I4 < 0.0 ? -1.0 : 0.0); }

// One Psi_AA term with coefficient mu (mu/2 (sqrt(I5) - S)^2); S from the closed-form I4 value at the same F.
template <int R, int C>
inline kernels::Derivs<R * C> kimAATerm(const kernels::RootContext<R, C> &ctx, const Vec<C> &a, double mu) {
  const Mat<C, C> A = kernels::fiberTensor<C>(a);
  const double S = kimStep(kernels::stretchInvariantValue<R, C>(ctx, A));
  const kernels::Derivs<R * C> I5 = kernels::invariantIVC<R, C>(ctx.F, A, ctx.order);
  const double r = std::sqrt(I5.value), d = r - S;
  return kernels::compose<R * C>(I5, 0.5 * mu * d * d, 0.5 * mu * (1.0 - S / r), 0.25 * mu * S / (r * r * r),
                                 ctx.order);
}

}  // namespace aries::energies
