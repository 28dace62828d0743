// Projection of a symmetric F-space Hessian to the nearest positive semi-definite matrix (eigenvalues clamped at 0).
// The element Hessian is B^T H_F B with B = dvec(F)/dx constant per element, so projecting H_F (9x9, 6x6, 4x4) is
// enough for a PSD element matrix and much cheaper than projecting the 12x12 / 9x9 / 6x6 element matrix.
#pragma once

#include "kernels/types.hpp"

#include <Eigen/Eigenvalues>

namespace aries::kernels {

template <int N>
inline Mat<N, N> projectToPSD(const Mat<N, N> &H) {
  const Mat<N, N> Hs = 0.5 * (H + H.transpose());
  // Already positive definite (common near rest): a Cholesky factorization is ~20x cheaper than an eigensolve.
  Eigen::LLT<Mat<N, N>> llt(Hs);
  if (llt.info() == Eigen::Success) return Hs;
  Eigen::SelfAdjointEigenSolver<Mat<N, N>> eig(Hs);
  const Vec<N> &lam = eig.eigenvalues();
  if (lam[0] >= 0.0) return Hs;
  const Mat<N, N> &Q = eig.eigenvectors();
  return Q * lam.cwiseMax(0.0).asDiagonal() * Q.transpose();
}

}  // namespace aries::kernels
