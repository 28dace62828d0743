// The linear simplices: the triangle (planar 2x2, or cloth 3x2 in 3D) and the tetrahedron (3x3). One point carrying
// the whole measure, F constant per cell: W = [-1^T Dm^-1; Dm^-1] from the rest edge matrix Dm (C x C) in the material
// frame (a triangle in 3D: its own oriented frame, clothFrame). Lumped mass measure / NV per vertex, which is also the
// consistent load (the row sums of the consistent mass). Output: XDMF Triangle / Tetrahedron, nodes as read.
#pragma once

#include "kernels/elements/element_type.hpp"
#include "kernels/enclosed_volume.hpp"

#include <type_traits>

namespace aries::kernels {

namespace simplex {

// Material frame of a rest triangle in 3D with (oriented) unit normal n: the projection of the global x and y axes
// onto its plane (a flat cloth in the xy plane with normals +z has u = x, v = y); falls back to (x,z) / (y,z). The
// frame is made right-handed about n, so every rest triangle of a consistently oriented surface has a positive
// area in it (and a flipped element of a UV map is one with det F < 0).
inline Mat<3, 2> orientedFrame(Mat<3, 2> E, const Vec<3> &n) {
  if (E.col(0).cross(E.col(1)).dot(n) < 0.0) E.col(1) *= -1.0;
  return E;
}

inline Mat<3, 2> clothFrame(const Vec<3> &n) {
  const Vec<3> axes[3] = {Vec<3>::UnitX(), Vec<3>::UnitY(), Vec<3>::UnitZ()};
  const int pairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  for (const auto &p : pairs) {
    Vec<3> e1 = axes[p[0]] - n.dot(axes[p[0]]) * n;
    if (e1.norm() < 0.3) continue;
    e1.normalize();
    Vec<3> e2 = axes[p[1]] - n.dot(axes[p[1]]) * n;
    e2 -= e1.dot(e2) * e1;
    if (e2.norm() < 0.3) continue;
    Mat<3, 2> E;
    E << e1, e2.normalized();
    return orientedFrame(E, n);
  }
  Mat<3, 2> E;
  E << n.unitOrthogonal(), n.cross(n.unitOrthogonal());
  return orientedFrame(E, n);
}

}  // namespace simplex

// The linear simplex with C reference dimensions and R-dimensional positions.
template <int R_, int C_>
struct LinearSimplex {
  static constexpr int R = R_, C = C_, NV = C + 1, NQ = 1;
  static constexpr int kOrder = 1;
  static constexpr bool kLinearSimplex = true;
  static constexpr CellKind kCells = C == 3 ? CellKind::Tetrahedron : CellKind::Triangle;
  static constexpr const char *kName =
      C == 3 ? "linear tetrahedron (P1)" : R == 3 ? "cloth triangle" : "planar triangle";
  static constexpr const char *kMeshHas = C == 3 ? "has linear tetrahedra" : "has triangles";
  static constexpr const char *kXdmfTopology = C == 3 ? "Tetrahedron" : "Triangle";
  static constexpr const char *kFoldHint = "";
  using Face = std::conditional_t<C == 3, face::Tri3, void>;
  static constexpr int outputNode(int k) { return k; }

  // X: the rest vertices (NV x 3; z = 0 for a planar mesh). embedded: a triangle given in 3D (cloth, or a UV map's
  // rest triangles), measured in its own material frame.
  static double rest(const Mat<NV, 3> &X, bool embedded, std::array<Mat<NV, C>, NQ> *W, std::array<double, NQ> *w,
                     double *measure) {
    Mat<C, C> Dm;
    if constexpr (C == 2) {
      if (embedded) {
        const Vec<3> e1 = (X.row(1) - X.row(0)).transpose(), e2 = (X.row(2) - X.row(0)).transpose();
        Vec<3> n = e1.cross(e2);
        n = n.norm() > 0.0 ? Vec<3>(n.normalized()) : Vec<3>::UnitZ();
        const Mat<3, 2> E = simplex::clothFrame(n);
        Dm.col(0) = E.transpose() * e1;
        Dm.col(1) = E.transpose() * e2;
      }
    }
    if (C == 3 || !embedded)
      for (int k = 0; k < C; ++k) Dm.col(k) = (X.row(k + 1) - X.row(0)).transpose().template head<C>();
    const double det = Dm.determinant();
    const double signedMeasure = det / (C == 3 ? 6.0 : 2.0);
    *measure = std::abs(signedMeasure);
    const Mat<C, C> B = std::abs(det) > 0.0 ? Mat<C, C>(Dm.inverse()) : Mat<C, C>::Zero();
    (*W)[0].row(0) = -B.colwise().sum();
    (*W)[0].template bottomRows<C>() = B;
    (*w)[0] = *measure;
    return signedMeasure;
  }
  static double lumpedShare(double measure, const std::array<double, NQ> &, int) { return measure / NV; }
  static double consistentShare(double measure, const std::array<double, NQ> &, int) { return measure / NV; }
};

using Tri3Planar = LinearSimplex<2, 2>;
using Tri3Cloth = LinearSimplex<3, 2>;
using Tet4 = LinearSimplex<3, 3>;
template <>
struct ElementAt<2, 2, 3> {
  using type = Tri3Planar;
};
template <>
struct ElementAt<3, 2, 3> {
  using type = Tri3Cloth;
};
template <>
struct ElementAt<3, 3, 4> {
  using type = Tet4;
};

}  // namespace aries::kernels
