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
template <int R, int C, int NV, class KMat>
inline void addPointHessian(const Mat<R * C, R * C> &H, const Mat<NV, C> &W, KMat *K) {
  constexpr int NF = R * C, NDOF = NV * R;
  Eigen::Matrix<double, NF, NDOF> HB;  // H * B, B[(k,l),(u,k')] = delta_kk' W(u,l)
  for (int row = 0; row < NF; ++row)
    for (int u = 0; u < NV; ++u)
      for (int k = 0; k < R; ++k) {
        double s = 0.0;
        for (int l = 0; l < C; ++l) s += H(row, k * C + l) * W(u, l);
        HB(row, u * R + k) = s;
      }
  for (int v = 0; v < NV; ++v)
    for (int i = 0; i < R; ++i)
      for (int col = 0; col < NDOF; ++col) {
        double s = 0.0;
        for (int j = 0; j < C; ++j) s += W(v, j) * HB(i * C + j, col);
        (*K)(v * R + i, col) += s;
      }
}

// F at one point from the element's positions X (NV x R, one vertex per row): F = X^T W.
template <int R, int C, int NV>
inline Mat<R, C> pointDeformationGradient(const Mat<NV, R> &X, const Mat<NV, C> &W) {
  return X.transpose() * W;
}

}  // namespace aries::kernels
