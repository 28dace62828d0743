// The quadratic tetrahedron (P2, -element p2): 10 nodes, 4 points of degree 2, HRZ lumped mass, XDMF Tetrahedron_10,
// 6-node faces. Runs on a tetrahedral mesh under -element p2, its edge nodes at the edges' middles or, from a
// second-order gmsh mesh (type 11), where the file puts them (curved, isoparametric): mesh/mesh_quadratic.cpp.
#pragma once

#include "kernels/elements/element_type.hpp"
#include "kernels/enclosed_volume.hpp"

namespace aries::kernels {

// The quadratic tetrahedron (P2, 10 nodes, straight edges) on the reference tet (0,0,0), (1,0,0), (0,1,0), (0,0,1):
// barycentrics L0 = 1 - xi1 - xi2 - xi3, Lk = xi_k; corner k has N = Lk (2 Lk - 1), the node at the middle of edge ab
// has N = 4 La Lb. Nodes 0-3 are the corners, 4-9 the edges kEdges: VTK's order, so the node order is also the XDMF
// Tetrahedron_10 order (gmsh's 10-node tet swaps the last two: its node 8 is on edge 23, 9 on edge 13). F is linear in
// the element, so Psi(F) is no polynomial and no rule integrates it exactly; the 4-point rule (degree 2, positive
// weights) integrates the linearized stiffness grad N^T C grad N (degree 2) and the consistent load of a constant body
// force exactly, which is what the element's optimal convergence needs, and 4 points x 6 strains = 24 = 30 dofs - 6
// rigid motions leaves no spurious zero-energy mode. The 5-point degree-3 and 11-point degree-4 rules have a negative
// weight, which would break the per-point PSD filter's guarantee that the element Hessian is PSD.
namespace tet10 {

constexpr int kNodes = 10;
constexpr int kPoints = 4;
inline constexpr int kEdges[6][2] = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {1, 3}, {2, 3}};  // node 4 + k sits on kEdges[k]

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
// points (Tet10::consistentShare; tet10::consistentShare: its values on a straight-edged element, which the rule gives
// exactly, for the tests).
inline double lumpedShare(int node) { return node < 4 ? 1.0 / 36.0 : 4.0 / 27.0; }
inline double consistentShare(int node) { return node < 4 ? -1.0 / 20.0 : 1.0 / 5.0; }

}  // namespace tet10

struct Tet10 {
  static constexpr int R = 3, C = 3, NV = tet10::kNodes, NQ = tet10::kPoints;
  static constexpr int kOrder = 2;
  static constexpr bool kLinearSimplex = false;
  static constexpr CellKind kCells = CellKind::Tetrahedron;
  static constexpr const char *kName = "quadratic tetrahedron (P2)";
  static constexpr const char *kMeshHas = "has quadratic tetrahedra (-element p2)";
  static constexpr const char *kXdmfTopology = "Tetrahedron_10";
  static constexpr const char *kFoldHint = "";
  using Face = face::Tri6;
  static constexpr int outputNode(int k) { return k; }  // the node order is VTK's

  static double rest(const Mat<NV, 3> &X, bool, std::array<Mat<NV, C>, NQ> *W, std::array<double, NQ> *w,
                     double *measure) {
    return pointRuleMeasure<NQ>(tet10::restPoints(X, W, w), w, measure);
  }
  // Gravity's consistent load int N_v, summed over the points: -measure / 20 at a straight element's corner and
  // measure / 5 at its edge nodes (a curved one's to the rule's accuracy).
  static Vec<NV> pointShapeValues(int q) { return tet10::shapeValues(tet10::pointBarycentrics(q)); }
  static double consistentShare(double, const std::array<double, NQ> &w, int v) {
    return pointRuleIntegral<Tet10>(w, v);
  }
  // HRZ (the corners' row sums are negative): the straight element's fractions of its volume, also on a curved one.
  static double lumpedShare(double measure, const std::array<double, NQ> &, int v) {
    return measure * tet10::lumpedShare(v);
  }
};
template <>
struct ElementAt<3, 3, 10> {
  using type = Tet10;
};

}  // namespace aries::kernels
