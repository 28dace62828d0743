// The trilinear hexahedron (Q1): 8 vertices, 2x2x2 Gauss points (full integration: exact for the trilinear mass and
// for the stiffness of a parallelepiped), lumped mass by row sums, XDMF Hexahedron in VTK order, bilinear 4-node faces.
// Runs on a mesh of hexahedra (gmsh type 5).
#pragma once

#include "kernels/elements/element_type.hpp"
#include "kernels/enclosed_volume.hpp"

namespace aries::kernels {

// The trilinear hexahedron (Q1) on PETSc's reference cell [-1, 1]^3, vertices in DMPlex closure order: the bottom face
// (xi_3 = -1) (-1,-1), (-1,1), (1,1), (1,-1), then the top face (xi_3 = 1) (-1,-1), (1,-1), (1,1), (-1,1).
// (gmsh and VTK number the same vertices 0, 3, 2, 1, 4, 5, 6, 7: vtkFromClosure.)
namespace hex8 {

constexpr int kVertices = 8;
constexpr int kPoints = 8;
inline constexpr double kReference[kVertices][3] = {{-1, -1, -1}, {-1, 1, -1}, {1, 1, -1}, {1, -1, -1},
                                             {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
inline constexpr int kVtkFromClosure[kVertices] = {0, 3, 2, 1, 4, 5, 6, 7};  // VTK/gmsh vertex k = closure vertex [k]

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

struct Hex8 {
  static constexpr int R = 3, C = 3, NV = hex8::kVertices, NQ = hex8::kPoints;
  static constexpr int kOrder = 1;
  static constexpr bool kLinearSimplex = false;
  static constexpr CellKind kCells = CellKind::Hexahedron;
  static constexpr const char *kName = "trilinear hexahedron (Q1)";
  static constexpr const char *kMeshHas = "has hexahedra";
  static constexpr const char *kXdmfTopology = "Hexahedron";
  static constexpr const char *kFoldHint =
      " (det J <= 0 at some Gauss point: a folded hexahedron or vertices out of gmsh's order)";
  using Face = face::Quad4;
  static constexpr int outputNode(int k) { return hex8::kVtkFromClosure[k]; }

  static double rest(const Mat<NV, 3> &X, bool, std::array<Mat<NV, C>, NQ> *W, std::array<double, NQ> *w,
                     double *measure) {
    return pointRuleMeasure<NQ>(hex8::restPoints(X, W, w), w, measure);
  }
  // The row sums of the consistent mass, sum_q w_q N_v(xi_q): exact for a parallelepiped (measure / 8), positive on
  // any valid hexahedron; gravity's consistent load is the same.
  static Vec<NV> pointShapeValues(int q) { return hex8::shapeValues(hex8::gaussPoint(q)); }
  static double consistentShare(double, const std::array<double, NQ> &w, int v) {
    return pointRuleIntegral<Hex8>(w, v);
  }
  static double lumpedShare(double measure, const std::array<double, NQ> &w, int v) {
    return std::abs(consistentShare(measure, w, v));
  }
};
template <>
struct ElementAt<3, 3, 8> {
  using type = Hex8;
};

}  // namespace aries::kernels
