// Eigenvalue filtering of a symmetric F-space Hessian for projected Newton. The element Hessian is B^T H_F B with
// B = dvec(F)/dx constant per element, so filtering H_F (9x9, 6x6, 4x4) is enough for a PSD element matrix and much
// cheaper than filtering the 12x12 / 9x9 / 6x6 element matrix.
//
// Filters (Newton solver option -psd_projection, docs/options.md):
//   Clamp  negative eigenvalues -> 0: the nearest PSD matrix (Teran et al. 2005, the classic projected Newton);
//   Abs    negative eigenvalues -> |lambda| (Chen et al. 2024, "Stabler Neo-Hookean Simulation: Absolute Eigenvalue
//          Filtering for Projected Newton"): a negative-curvature mode keeps its magnitude, so the Newton step along it
//          is as short as the local curvature says instead of being limited by the other terms only;
//   None   the true Hessian (symmetrized), indefinite where the energy is not convex.
#pragma once

#include "kernels/dense_decompositions.hpp"
#include "kernels/types.hpp"

namespace aries::kernels {

enum class EigenFilter { Clamp, Abs, None };

// The filter applied to a spectrum.
template <int N>
inline Vec<N> filterSpectrum(const Vec<N> &lambda, EigenFilter filter) {
  if (filter == EigenFilter::Clamp) return lambda.cwiseMax(0.0);
  if (filter == EigenFilter::Abs) return lambda.cwiseAbs();
  return lambda;
}

template <int N>
inline Mat<N, N> filterEigenvalues(const Mat<N, N> &H, EigenFilter filter) {
  const Mat<N, N> Hs = 0.5 * (H + H.transpose());
  if (filter == EigenFilter::None) return Hs;
  // Already positive definite (common near rest): a Cholesky factorization is ~20x cheaper than an eigensolve.
  Eigen::LLT<Mat<N, N>> llt(Hs);
  if (llt.info() == Eigen::Success) return Hs;
  const SymmetricEigen<N> eig = symmetricEigen<N>(Hs);
  const Vec<N> &lam = eig.values;
  if (lam[0] >= 0.0) return Hs;
  const Mat<N, N> &Q = eig.vectors;
  return Q * filterSpectrum<N>(lam, filter).asDiagonal() * Q.transpose();
}

// The nearest PSD matrix (eigenvalues clamped at 0).
template <int N>
inline Mat<N, N> projectToPSD(const Mat<N, N> &H) {
  return filterEigenvalues<N>(H, EigenFilter::Clamp);
}

}  // namespace aries::kernels
