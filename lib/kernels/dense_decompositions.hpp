// The kernels' dense decompositions of small fixed-size matrices, in one place for every kernel and tool that needs
// them: the symmetric eigen-decomposition (Eigen's SelfAdjointEigenSolver: Householder tridiagonalization, then
// implicit symmetric QR) for the PSD filters (kernels/psd_projection.hpp), the root function's Horn fallback
// (kernels/root_function.hpp) and the reports of a Hessian's spectrum; and the SVD (Eigen's two-sided JacobiSVD) for
// the SVD baselines (kernels/svd_polar.hpp) and the principal stretches (kernels/stress_measures.hpp).
//
// Function templates that are not inline, on purpose: instantiating one of Eigen's solvers for one size costs 1-5 s of
// compile (clang 14, -O2) in every translation unit that uses it, and most of aries' units used several. aries' own
// build defines ARIES_KERNEL_INSTANCES (CMakeLists.txt, on aries_energies and what links it): there the sizes below are
// compiled once, in lib/energies/kernel_instances.cpp, and every other file calls that copy (two fresh clones' builds
// back to back, 2 cores: 433 CPU-s before, 369 after). Code that includes the kernels without the macro (the installed
// package's users) instantiates what it uses, as with any template. Both give the same numbers: the same code,
// compiled with the same flags.
#pragma once

#include "kernels/types.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

namespace aries::kernels {

template <int N>
struct SymmetricEigen {
  Vec<N> values;      // ascending
  Mat<N, N> vectors;  // column k: the unit eigenvector of values[k]
};

// A's eigenvalues and eigenvectors; A must be symmetric (only its lower triangle is read).
template <int N>
SymmetricEigen<N> symmetricEigen(const Mat<N, N> &A) {
  const Eigen::SelfAdjointEigenSolver<Mat<N, N>> eig(A);
  return {eig.eigenvalues(), eig.eigenvectors()};
}

// A's eigenvalues alone (ascending), cheaper than symmetricEigen where the vectors are not needed.
template <int N>
Vec<N> symmetricEigenvalues(const Mat<N, N> &A) {
  return Eigen::SelfAdjointEigenSolver<Mat<N, N>>(A, Eigen::EigenvaluesOnly).eigenvalues();
}

// F = U diag(s) V^T with U (R x R) and V (C x C) orthogonal and s >= 0 descending (Eigen's convention: U and V may
// be reflections; kernels/svd_polar.hpp's signedSvd makes them rotations).
template <int R, int C>
struct FullSvd {
  Mat<R, R> U;
  Vec<C> s;
  Mat<C, C> V;
};

template <int R, int C>
FullSvd<R, C> fullSvd(const Mat<R, C> &F) {
  const Eigen::JacobiSVD<Mat<R, C>> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  return {svd.matrixU(), svd.singularValues(), svd.matrixV()};
}

// The singular values alone (descending).
template <int R, int C>
Vec<C> singularValues(const Mat<R, C> &F) {
  return Eigen::JacobiSVD<Mat<R, C>>(F).singularValues();
}

// The sizes compiled once. Eigen: the F-space Hessians of the planar, cloth and solid shapes (4, 6, 9), the Horn
// matrix (4), and the element and face matrices the filters see (6, 9, 12, 18, 24, 30: planar and cloth triangles,
// tetrahedra, six-node faces, hexahedra, ten-node tetrahedra). SVD: the three shapes of F. Any other size is
// instantiated where it is used.
#define ARIES_SYMMETRIC_EIGEN_SIZES(X) X(4) X(6) X(9) X(12) X(18) X(24) X(30)
#define ARIES_SVD_SHAPES(X) X(2, 2) X(3, 3) X(3, 2)

#ifdef ARIES_KERNEL_INSTANCES
#define ARIES_SYMMETRIC_EIGEN_EXTERN(N)                                    \
  extern template SymmetricEigen<N> symmetricEigen<N>(const Mat<N, N> &); \
  extern template Vec<N> symmetricEigenvalues<N>(const Mat<N, N> &);
#define ARIES_SVD_EXTERN(R, C)                                         \
  extern template FullSvd<R, C> fullSvd<R, C>(const Mat<R, C> &); \
  extern template Vec<C> singularValues<R, C>(const Mat<R, C> &);
ARIES_SYMMETRIC_EIGEN_SIZES(ARIES_SYMMETRIC_EIGEN_EXTERN)
ARIES_SVD_SHAPES(ARIES_SVD_EXTERN)
#undef ARIES_SYMMETRIC_EIGEN_EXTERN
#undef ARIES_SVD_EXTERN
#endif

}  // namespace aries::kernels
