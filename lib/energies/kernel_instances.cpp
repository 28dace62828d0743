// The kernels' dense decompositions, compiled once for aries' own build (ARIES_KERNEL_INSTANCES: see
// kernels/dense_decompositions.hpp for why and for the sizes).
#include "kernels/dense_decompositions.hpp"

#ifndef ARIES_KERNEL_INSTANCES
#error "kernel_instances.cpp is compiled with ARIES_KERNEL_INSTANCES (CMakeLists.txt, aries_energies)"
#endif

namespace aries::kernels {

#define ARIES_SYMMETRIC_EIGEN_INSTANCE(N)                           \
  template SymmetricEigen<N> symmetricEigen<N>(const Mat<N, N> &); \
  template Vec<N> symmetricEigenvalues<N>(const Mat<N, N> &);
#define ARIES_SVD_INSTANCE(R, C)                                 \
  template FullSvd<R, C> fullSvd<R, C>(const Mat<R, C> &); \
  template Vec<C> singularValues<R, C>(const Mat<R, C> &);
ARIES_SYMMETRIC_EIGEN_SIZES(ARIES_SYMMETRIC_EIGEN_INSTANCE)
ARIES_SVD_SHAPES(ARIES_SVD_INSTANCE)
#undef ARIES_SYMMETRIC_EIGEN_INSTANCE
#undef ARIES_SVD_INSTANCE

}  // namespace aries::kernels
