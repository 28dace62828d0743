// What an element type is (pure math and facts, no PETSc): each file of this folder defines one (or a family), and
// fem/element_types.hpp registers it with one line. An element type E provides
//   E::R, E::C            the shape of F it gives (R x C: 3x3 solids, 2x2 planar, 3x2 cloth)
//   E::NV, E::NQ          nodes per element and quadrature points per element
//   E::kName              what it is called in messages and docs ("trilinear hexahedron (Q1)")
//   E::kCells, E::kOrder  the mesh kind it runs on: the polytope of the mesh's cells and the order of its geometry
//                         (1: the cells' vertices; 2: a node on each edge too, -element p2)
//   E::kMeshHas           how a refusal names the mesh ("has hexahedra")
//   E::kXdmfTopology      the XDMF topology of its output, and E::outputNode(k): the element node written k-th
//   E::Face               its boundary faces' type (kernels/enclosed_volume.hpp; void for a 2D element: its faces are
//                         edges)
//   E::rest(X, embedded, &W, &w, &measure)
//                         W_q = dN/dX and w_q at each point from the rest node positions X (NV x 3, the element's node
//                         order); returns the signed rest measure (0: degenerate or folded, < 0: inverted)
//   E::lumpedShare(measure, w, v), E::consistentShare(measure, w, v)
//                         the rest measure node v gets in the lumped mass and in gravity's consistent load
//   E::kLinearSimplex     one point, F constant per cell: the fields that need it (the caricature's curvature) run only
//                         on such elements
//   E::kFoldHint          added to the message for a degenerate rest cell
// F at point q is F_q = sum_v x_v W_q.row(v) for every element (kernels/element_rules.hpp maps a point's PK1 and
// Hessian to the nodes), so the assembly, the energies and the safeguard never ask which element they run on.
#pragma once

#include "kernels/types.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace aries::kernels {

// The polytope of a mesh's cells, as an element type accepts it.
enum class CellKind { Triangle, Tetrahedron, Hexahedron };

// The element type with R x C deformation gradients and NV nodes (ElementAt<R, C, NV>::type): specialized in each
// element's file.
template <int R, int C, int NV>
struct ElementAt;
template <int R, int C, int NV>
using ElementOf = typename ElementAt<R, C, NV>::type;

// Rest data of an isoparametric 3D element with rest node positions X (NV x 3) at its NQ points: W_q = dN/dX =
// dN/dxi J^-1 (J = X^T dN/dxi, dN/dxi = gradients(q)) and the weight w_q = det J * pointWeight (the rule's weight on
// the reference cell). Returns the smallest det J over the points (a valid, consistently numbered cell has all of them
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

// The rest data of an element with a point rule, from its points' det J (minDet: the smallest, as
// isoparametricRestPoints returns): the measure is the sum of the weights; a cell numbered with the other orientation
// (every det J < 0) keeps W_q (F = I at rest) with positive weights. Returns its signed rest volume when det J has one
// sign at every point (negative: an inverted cell), and 0 when the signs differ (a folded cell or nodes out of order,
// which no reordering of the whole mesh fixes: reported as degenerate).
template <int NQ>
inline double pointRuleMeasure(double minDet, std::array<double, NQ> *weight, double *measure) {
  double volume = 0.0, maxDet = -std::numeric_limits<double>::infinity();
  for (double w : *weight) {
    volume += w;
    maxDet = std::max(maxDet, w);
  }
  *measure = std::abs(volume);
  if (maxDet < 0.0)
    for (double &w : *weight) w = -w;
  return minDet > 0.0 || maxDet < 0.0 ? volume : 0.0;
}

// int N_v over an element with a point rule: sum_q w_q N_v(xi_q) (E::pointShapeValues(q): every N at point q). The row
// sums of the consistent mass, exact wherever the rule integrates N_v.
template <class E>
inline double pointRuleIntegral(const std::array<double, E::NQ> &w, int v) {
  double share = 0.0;
  for (int q = 0; q < E::NQ; ++q) share += w[q] * E::pointShapeValues(q)[v];
  return share;
}

}  // namespace aries::kernels
