// Elements evaluated at quadrature points (pure math, no PETSc): the deformation gradient at point q of an element
// with NV vertices is F_q = sum_v x_v W_q.row(v), W_q = dN/dX at the point (NV x C), and the element's energy is
// sum_q w_q Psi(F_q), w_q the rest measure the point carries. The closed-form kernels take any F, so an element is
// only its W_q and w_q, which each element type's file computes (kernels/elements/: the linear simplices, the trilinear
// hexahedron, the quadratic tetrahedron). This file maps one point's PK1 and Hessian (flattened row-major in F,
// kernels/types.hpp) to the element's vertex dofs (vertex-major: dof v R + i), for assembly and for the element FD
// tests, so both use the same code.
#pragma once

#include "kernels/types.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace aries::kernels {

// Adds the point's gradient w P (P = dPsi/dF, R x C) to the element gradient g (NV R): g_(v,i) += w sum_j P_ij W_vj.
template <int R, int C, int NV>
inline void addPointGradient(const Mat<R, C> &wP, const Mat<NV, C> &W, Vec<NV * R> *g) {
  for (int v = 0; v < NV; ++v) g->template segment<R>(v * R) += wP * W.row(v).transpose();
}

// Adds B^T H B to the element Hessian K ((NV R)^2, row-major): K[(v,i),(u,k)] += sum_jl H[(i,j),(k,l)] W(v,j) W(u,l).
// Written as 2 R small fixed-size products (H's column blocks times W^T, then W times HB's row blocks), which Eigen
// vectorizes (the same flops as scalar loops over the same sums; those loops were the largest single cost of a
// hexahedral Hessian assembly).
template <int R, int C, int NV, class KMat>
inline void addPointHessian(const Mat<R * C, R * C> &H, const Mat<NV, C> &W, KMat *K) {
  constexpr int NF = R * C, NDOF = NV * R;
  // HB = H B, B[(k,l),(u,k')] = delta_kk' W(u,l): HB(:, u R + k) = H(:, k C .. k C + C - 1) W(u, :)^T
  Eigen::Matrix<double, NF, NDOF> HB;
  for (int k = 0; k < R; ++k) {
    const Eigen::Matrix<double, NF, NV> block = H.template middleCols<C>(k * C).lazyProduct(W.transpose());
    for (int u = 0; u < NV; ++u) HB.col(u * R + k) = block.col(u);
  }
  // K((v,i), :) += sum_j W(v,j) HB(i C + j, :)
  for (int i = 0; i < R; ++i) {
    const Eigen::Matrix<double, NV, NDOF> rows = W.lazyProduct(HB.template middleRows<C>(i * C));
    for (int v = 0; v < NV; ++v) K->row(v * R + i) += rows.row(v);
  }
}

// F at one point from the element's positions X (NV x R, one vertex per row): F = X^T W.
template <int R, int C, int NV>
inline Mat<R, C> pointDeformationGradient(const Mat<NV, R> &X, const Mat<NV, C> &W) {
  return X.transpose() * W;
}

}  // namespace aries::kernels
