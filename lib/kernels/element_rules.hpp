// Elements evaluated at quadrature points (pure math, no PETSc): the deformation gradient at point q of an element
// with NV vertices is F_q = sum_v x_v W_q.row(v), W_q = dN/dX at the point (NV x C), and the element's energy is
// sum_q w_q Psi(F_q), w_q the rest measure the point carries. The closed-form kernels take any F, so an element is
// only its W_q and w_q: the linear simplex (one point, W = [-1^T Dm^-1; Dm^-1], w = rest measure) and the trilinear
// hexahedron Q1 (2x2x2 Gauss points). This file maps one point's PK1 and Hessian (flattened row-major in F,
// kernels/types.hpp) to the element's vertex dofs (vertex-major: dof v R + i), for assembly and for the element FD
// tests, so both use the same code.
#pragma once

#include "kernels/types.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace aries::kernels {

// The number of quadrature points of an element with NV nodes and C reference dimensions: 1 for simplices
// (F is constant on a linear simplex), 8 for the trilinear hexahedron (2x2x2 Gauss: exact for the trilinear mass and
// for the stiffness of a parallelepiped, the standard full integration of Q1), 4 for the quadratic tetrahedron (tet10
// below).
constexpr int quadraturePoints(int NV, int C) {
  return NV == C + 1 ? 1 : (C == 3 && NV == 8) ? 8 : (C == 3 && NV == 10) ? 4 : -1;
}

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

// Rest data of an isoparametric 3D element with rest node positions X (NV x 3) at its NQ points: W_q = dN/dX =
// dN/dxi J^-1 (J = X^T dN/dxi, dN/dxi = gradients(q)) and the weight w_q = det J * pointWeight (the rule's weight on the
// reference cell). Returns the smallest det J over the points (a valid, consistently numbered cell has all of them
// > 0); W_q is zero where det J = 0.
template <int NV, int NQ, class Gradients>
inline double isoparametricRestPoints(const Mat<NV, 3> &X, const Gradients &gradients, double pointWeight,
                                      std::array<Mat<NV, 3>, NQ> *W, std::array<double, NQ> *weight) {
  double minDet = std::numeric_limits<double>::infinity();
  for (int q = 0; q < NQ; ++q) {
    const Mat<NV, 3> G = gradients(q);
    const Mat<3, 3> J = X.transpose() * G;
    const double det = J.determinant();
    minDet = std::min(minDet, det);
    (*weight)[q] = det * pointWeight;
    (*W)[q] = det != 0.0 ? Mat<NV, 3>(G * J.inverse()) : Mat<NV, 3>::Zero();
  }
  return minDet;
}

// The trilinear hexahedron (Q1) on PETSc's reference cell [-1, 1]^3, vertices in DMPlex closure order: the bottom face
// (xi_3 = -1) (-1,-1), (-1,1), (1,1), (1,-1), then the top face (xi_3 = 1) (-1,-1), (1,-1), (1,1), (-1,1).
// (gmsh and VTK number the same vertices 0, 3, 2, 1, 4, 5, 6, 7: vtkFromClosure.)
namespace hex8 {

constexpr int kVertices = 8;
constexpr int kPoints = 8;
constexpr double kReference[kVertices][3] = {{-1, -1, -1}, {-1, 1, -1}, {1, 1, -1}, {1, -1, -1},
                                             {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
constexpr int kVtkFromClosure[kVertices] = {0, 3, 2, 1, 4, 5, 6, 7};  // VTK/gmsh vertex k = closure vertex [k]

// Gauss point q (weight 1 each): xi = (+-1, +-1, +-1) / sqrt(3), bit j of q giving the sign of xi_j.
inline Vec<3> gaussPoint(int q) {
  const double g = 1.0 / std::sqrt(3.0);
  return Vec<3>((q & 1) ? g : -g, (q & 2) ? g : -g, (q & 4) ? g : -g);
}

// Shape functions N_v(xi) = prod_j (1 + r_vj xi_j) / 8 and their reference gradients dN_v/dxi (8 x 3).
inline Vec<kVertices> shapeValues(const Vec<3> &xi) {
  Vec<kVertices> N;
  for (int v = 0; v < kVertices; ++v)
    N[v] = (1 + kReference[v][0] * xi[0]) * (1 + kReference[v][1] * xi[1]) * (1 + kReference[v][2] * xi[2]) / 8.0;
  return N;
}

inline Mat<kVertices, 3> shapeGradients(const Vec<3> &xi) {
  Mat<kVertices, 3> G;
  for (int v = 0; v < kVertices; ++v)
    for (int j = 0; j < 3; ++j) {
      double p = kReference[v][j] / 8.0;
      for (int k = 0; k < 3; ++k)
        if (k != j) p *= 1 + kReference[v][k] * xi[k];
      G(v, j) = p;
    }
  return G;
}

// Rest data of one hexahedron with rest positions X (8 x 3, closure order): at each Gauss point W_q = dN/dX =
// dN/dxi J^-1 (J = X^T dN/dxi) and the weight w_q = det J (Gauss weight 1). Returns the smallest det J over the points
// (a valid, consistently numbered cell has all of them > 0); W_q is zero where det J = 0.
inline double restPoints(const Mat<kVertices, 3> &X, std::array<Mat<kVertices, 3>, kPoints> *W,
                         std::array<double, kPoints> *weight) {
  return isoparametricRestPoints<kVertices, kPoints>(X, [](int q) { return shapeGradients(gaussPoint(q)); }, 1.0, W,
                                                     weight);
}

}  // namespace hex8

// The quadratic tetrahedron (P2, 10 nodes, straight edges) on the reference tet (0,0,0), (1,0,0), (0,1,0), (0,0,1):
// barycentrics L0 = 1 - xi1 - xi2 - xi3, Lk = xi_k; corner k has N = Lk (2 Lk - 1), the node at the middle of edge
// (a, b) has N = 4 La Lb. Nodes 0-3 are the corners, 4-9 the edges kEdges: VTK's order, so the node order is also
// the XDMF Tetrahedron_10 order (gmsh's 10-node tet swaps the last two: its node 8 is on edge 23, 9 on edge 13). F is linear in the element, so Psi(F) is no polynomial and no rule
// integrates it exactly; the 4-point rule (degree 2, positive weights) integrates the linearized stiffness grad N^T C
// grad N (degree 2) and the consistent load of a constant body force exactly, which is what the element's optimal
// convergence needs, and 4 points x 6 strains = 24 = 30 dofs - 6 rigid motions leaves no spurious zero-energy mode.
// The 5-point degree-3 and 11-point degree-4 rules have a negative weight, which would break the per-point PSD
// filter's guarantee that the element Hessian is PSD.
namespace tet10 {

constexpr int kNodes = 10;
constexpr int kPoints = 4;
constexpr int kEdges[6][2] = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {1, 3}, {2, 3}};  // node 4 + k sits on kEdges[k]

// Barycentric coordinates of point q: (5 + 3 sqrt 5) / 20 at corner q, (5 - sqrt 5) / 20 at the others; weight 1/24
// each (the reference volume is 1/6).
inline Vec<4> pointBarycentrics(int q) {
  const double a = (5.0 - std::sqrt(5.0)) / 20.0, b = 1.0 - 3.0 * a;
  Vec<4> L = Vec<4>::Constant(a);
  L[q] = b;
  return L;
}
constexpr double kPointWeight = 1.0 / 24.0;

inline Vec<kNodes> shapeValues(const Vec<4> &L) {
  Vec<kNodes> N;
  for (int k = 0; k < 4; ++k) N[k] = L[k] * (2.0 * L[k] - 1.0);
  for (int e = 0; e < 6; ++e) N[4 + e] = 4.0 * L[kEdges[e][0]] * L[kEdges[e][1]];
  return N;
}

// dN/dxi (10 x 3) at barycentrics L: dL0/dxi = (-1, -1, -1), dLk/dxi = e_k.
inline Mat<kNodes, 3> shapeGradients(const Vec<4> &L) {
  Mat<4, 3> dL;
  dL << -1, -1, -1, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  Mat<kNodes, 3> G;
  for (int k = 0; k < 4; ++k) G.row(k) = (4.0 * L[k] - 1.0) * dL.row(k);
  for (int e = 0; e < 6; ++e) {
    const int a = kEdges[e][0], b = kEdges[e][1];
    G.row(4 + e) = 4.0 * (L[a] * dL.row(b) + L[b] * dL.row(a));
  }
  return G;
}

// Rest data of one quadratic tetrahedron with rest node positions X (10 x 3, node order above): W_q = dN/dxi J^-1 and
// w_q = det J / 24 at each point (isoparametricRestPoints). Returns the smallest det J (constant for straight edges).
inline double restPoints(const Mat<kNodes, 3> &X, std::array<Mat<kNodes, 3>, kPoints> *W,
                         std::array<double, kPoints> *weight) {
  return isoparametricRestPoints<kNodes, kPoints>(X, [](int q) { return shapeGradients(pointBarycentrics(q)); },
                                                  kPointWeight, W, weight);
}

// The lumped mass of a straight-edged P2 tet of volume V (HRZ: the consistent mass's diagonal, int N_i^2 = V/70 at a
// corner and 8V/105 at an edge node, scaled to the total): V/36 per corner, 4V/27 per edge node, all positive (the
// row sums, int N_i = -V/20 at a corner, are not). Gravity uses the consistent load int N_i instead, summed over the
// points (fem/rest_geometry.cpp; consistentShare: its values on a straight-edged element, which the rule gives exactly).
inline double lumpedShare(int node) { return node < 4 ? 1.0 / 36.0 : 4.0 / 27.0; }
inline double consistentShare(int node) { return node < 4 ? -1.0 / 20.0 : 1.0 / 5.0; }

}  // namespace tet10

}  // namespace aries::kernels
