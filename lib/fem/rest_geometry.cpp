// Rest geometry: each cell's vertices, rest edge matrix Dm in the material frame (a 3D triangle in its own oriented
// frame), W = [-1^T Dm^-1; Dm^-1] and rest measure; one clear error for a degenerate or inverted rest cell; the total
// rest measure and the lumped vertex masses.
#include "fem/discretization_impl.hpp"

#include "core/errors.hpp"

#include <petscdmplex.h>

#include <cmath>
#include <limits>
#include <sstream>

namespace aries::fem {

using core::collectiveCheck;

namespace {

// Material frame of a rest triangle in 3D with (oriented) unit normal n: the projection of the global x and y axes
// onto its plane (a flat cloth in the xy plane with normals +z has u = x, v = y); falls back to (x,z) / (y,z). The
// frame is made right-handed about n, so every rest triangle of a consistently oriented surface has a positive
// area in it (and a flipped element of a UV map is one with det F < 0).
Eigen::Matrix<double, 3, 2> orientedFrame(Eigen::Matrix<double, 3, 2> E, const Eigen::Vector3d &n) {
  if (E.col(0).cross(E.col(1)).dot(n) < 0.0) E.col(1) *= -1.0;
  return E;
}

Eigen::Matrix<double, 3, 2> clothFrame(const Eigen::Vector3d &n) {
  const Eigen::Vector3d axes[3] = {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ()};
  const int pairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  for (const auto &p : pairs) {
    Eigen::Vector3d e1 = axes[p[0]] - n.dot(axes[p[0]]) * n;
    if (e1.norm() < 0.3) continue;
    e1.normalize();
    Eigen::Vector3d e2 = axes[p[1]] - n.dot(axes[p[1]]) * n;
    e2 -= e1.dot(e2) * e1;
    if (e2.norm() < 0.3) continue;
    Eigen::Matrix<double, 3, 2> E;
    E << e1, e2.normalized();
    return orientedFrame(E, n);
  }
  Eigen::Matrix<double, 3, 2> E;
  E << n.unitOrthogonal(), n.cross(n.unitOrthogonal());
  return orientedFrame(E, n);
}

}  // namespace

// A linear simplex: rest edge matrix Dm in the material frame (C x C), W = [-1^T Dm^-1; Dm^-1], one point carrying
// the whole measure. Returns the signed rest measure.
template <int R, int C, int NV>
double DiscretizationT<R, C, NV>::simplexRest(Cell *cellp, PetscInt spaceDim) const {
  Cell &cell = *cellp;
  kernels::Mat<C, C> Dm;
  bool projected = false;
  if constexpr (C == 2) {
    if (spaceDim == 3) {  // cloth, or a UV map: the 3D triangle in its material frame
      const Eigen::Vector3d X0 = verts_[cell.vertex[0]].rest;
      const Eigen::Vector3d e1 = verts_[cell.vertex[1]].rest - X0, e2 = verts_[cell.vertex[2]].rest - X0;
      Eigen::Vector3d n = e1.cross(e2);
      n = n.norm() > 0.0 ? Eigen::Vector3d(n.normalized()) : Eigen::Vector3d::UnitZ();
      const Eigen::Matrix<double, 3, 2> E = clothFrame(n);
      Dm.col(0) = E.transpose() * e1;
      Dm.col(1) = E.transpose() * e2;
      projected = true;
    }
  }
  if (!projected)
    for (int k2 = 0; k2 < C; ++k2)
      Dm.col(k2) = (verts_[cell.vertex[k2 + 1]].rest - verts_[cell.vertex[0]].rest).template head<C>();
  const double det = Dm.determinant();
  const double signedMeasure = det / (C == 3 ? 6.0 : 2.0);
  cell.measure = std::abs(signedMeasure);
  const kernels::Mat<C, C> B = std::abs(det) > 0.0 ? kernels::Mat<C, C>(Dm.inverse()) : kernels::Mat<C, C>::Zero();
  cell.W[0].row(0) = -B.colwise().sum();
  cell.W[0].template bottomRows<C>() = B;
  cell.weight[0] = cell.measure;
  return signedMeasure;
}

// An element with a point rule (kernels/element_rules.hpp): W and det J at the 2x2x2 Gauss points of a trilinear
// hexahedron or the 4 points of a quadratic tetrahedron. Returns its signed rest volume for the rest-cell check when
// det J has one sign at every point (negative: an inverted cell), and 0 when the signs differ (a folded cell or
// vertices out of order, which no reordering of the whole mesh fixes: reported as degenerate).
template <int R, int C, int NV>
double DiscretizationT<R, C, NV>::quadratureRest(Cell *cell) const {
  if constexpr (R == 3 && C == 3 && (NV == 8 || NV == 10)) {
    kernels::Mat<NV, 3> X;
    for (int v = 0; v < NV; ++v) X.row(v) = verts_[cell->vertex[v]].rest.transpose();
    double minDet;
    if constexpr (NV == 8) minDet = kernels::hex8::restPoints(X, &cell->W, &cell->weight);
    else minDet = kernels::tet10::restPoints(X, &cell->W, &cell->weight);
    double volume = 0.0, maxDet = -std::numeric_limits<double>::infinity();
    for (double w : cell->weight) {
      volume += w;
      maxDet = std::max(maxDet, w);
    }
    cell->measure = std::abs(volume);
    if (maxDet < 0.0)  // numbered with the other orientation: W_q still gives F = I at rest; the weights are volumes
      for (double &w : cell->weight) w = -w;
    return minDet > 0.0 || maxDet < 0.0 ? volume : 0.0;
  } else {
    return 0.0;
  }
}

template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::setupRestCells(const Mesh &mesh,
                                                     const std::vector<std::pair<DMLabel, PetscInt>> &regionLabels) {
  PetscFunctionBeginUser;
  const PetscInt nc = mesh.numCells();
  std::vector<Cell> &cells = cells_.cells();
  cells.resize(nc);
  std::vector<double> signedMeasure(nc);
  for (PetscInt k = 0; k < nc; ++k) {
    Cell &cell = cells[k];
    PetscInt point = mesh.cStart + k;  // the DM cell whose labels give the region
    if (mesh.quadratic) {  // the element's nodes, kernels::tet10's order (mesh/mesh_quadratic.cpp)
      std::copy(mesh.elementNodes[k].begin(), mesh.elementNodes[k].end(), cell.vertex.begin());
      point = mesh.elementCell[k];
    } else {
      PetscInt ncl, *closure = nullptr, n = 0;
      PetscCall(DMPlexGetTransitiveClosure(mesh.dm, point, PETSC_TRUE, &ncl, &closure));
      for (PetscInt i = 0; i < ncl && n < NV; ++i) {  // closure order (kernels/element_rules.hpp for hexahedra)
        const PetscInt p = closure[2 * i];
        if (p >= mesh.vStart && p < mesh.vEnd) cell.vertex[n++] = p - mesh.vStart;
      }
      PetscCall(DMPlexRestoreTransitiveClosure(mesh.dm, point, PETSC_TRUE, &ncl, &closure));
    }
    if constexpr (NV == C + 1) {
      signedMeasure[k] = simplexRest(&cell, mesh.spaceDim);
    } else {
      signedMeasure[k] = quadratureRest(&cell);
    }
    cell.owned = mesh.cellOwned[k];
    cell.region = 0;
    for (size_t r = 0; r < regionLabels.size(); ++r) {
      PetscInt val;
      PetscCall(DMLabelGetValue(regionLabels[r].first, point, &val));
      if (val == regionLabels[r].second) cell.region = static_cast<int>(r + 1);
    }
  }
  PetscCall(checkRestCells(mesh, signedMeasure));
  double localMeasure = 0.0;
  for (const auto &cell : cells)
    if (cell.owned) localMeasure += cell.measure;
  PetscCallMPI(MPI_Allreduce(&localMeasure, &restMeasure_, 1, MPI_DOUBLE, MPI_SUM, comm()));
  PetscFunctionReturn(0);
}

// Degenerate or inverted rest cells: one clear error naming the (natural, 0-based gmsh-order) cell. Inverted means
// oriented against the majority of the mesh's cells.
template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::checkRestCells(const Mesh &mesh, const std::vector<double> &signedMeasure) const {
  PetscFunctionBeginUser;
  const double tiny = 1e-14 * std::pow(mesh.diagonal, C);
  long pos = 0, neg = 0;
  for (double s : signedMeasure) (s > 0 ? pos : neg)++;
  long tot[2] = {pos, neg}, gtot[2];
  PetscCallMPI(MPI_Allreduce(tot, gtot, 2, MPI_LONG, MPI_SUM, comm()));
  const double majority = gtot[0] >= gtot[1] ? 1.0 : -1.0;
  std::string msg;
  for (size_t c = 0; c < signedMeasure.size() && msg.empty(); ++c) {
    const double s = signedMeasure[c];
    if (std::abs(s) <= tiny) {
      std::ostringstream o;
      o << "mesh '" << mesh.filename << "': cell " << mesh.naturalCell[c] << " (0-based, gmsh element order) is "
        << "degenerate: rest " << (C == 3 ? "volume " : "area ") << s
        << (NV == 8 ? " (det J <= 0 at some Gauss point: a folded hexahedron or vertices out of gmsh's order)" : "")
        << "; fix or remove it";
      msg = o.str();
    } else if (s * majority < 0.0) {
      std::ostringstream o;
      o << "mesh '" << mesh.filename << "': cell " << mesh.naturalCell[c] << " (0-based, gmsh element order) is "
        << "inverted: signed rest " << (C == 3 ? "volume " : "area ") << s * majority
        << " (its orientation disagrees with the mesh); reorder its nodes";
      msg = o.str();
    }
  }
  PetscCall(collectiveCheck(comm(), !msg.empty(), msg));
  PetscFunctionReturn(0);
}

// The rest volume an element gives node v for gravity, the consistent load int N_v: the row sums of its consistent
// mass, sum_q w_q N_v(xi_q) (exact where the element is affine or a parallelepiped: the point rules integrate N_v);
// measure / NV on a simplex, measure / 8 on a parallelepiped, -measure / 20 at a straight quadratic tetrahedron's
// corner and measure / 5 at its edge nodes (a curved one's, from a second-order mesh, to the rule's accuracy).
template <int R, int C, int NV>
double DiscretizationT<R, C, NV>::consistentShare(const Cell &cell, int v) const {
  double share = 0.0;
  if constexpr (NV == 8)
    for (int q = 0; q < NQ; ++q) share += cell.weight[q] * kernels::hex8::shapeValues(kernels::hex8::gaussPoint(q))[v];
  else if constexpr (NV == 10)
    for (int q = 0; q < NQ; ++q)
      share += cell.weight[q] * kernels::tet10::shapeValues(kernels::tet10::pointBarycentrics(q))[v];
  return share;
}

// ... and for the lumped mass: the row sums where they are positive (Q1), HRZ for the quadratic tetrahedron (its
// corners' row sums are negative; kernels::tet10::lumpedShare: the straight element's fractions of its volume, also on
// a curved one).
template <int R, int C, int NV>
double DiscretizationT<R, C, NV>::lumpedShare(const Cell &cell, int v) const {
  if constexpr (NV == 10) return cell.measure * kernels::tet10::lumpedShare(v);
  return std::abs(consistentShare(cell, v));
}

// Lumped mass and gravity's consistent mass from every owned cell, summed over the ranks sharing a vertex: both are
// density * measure / NV on a simplex (the row sums of its consistent mass); lumpedShare and consistentShare on
// elements with a point rule.
template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::setupMass(const Mesh &mesh) {
  PetscFunctionBeginUser;
  mass_.assign(mesh.vEnd - mesh.vStart, 0.0);
  gravityMass_.assign(mesh.vEnd - mesh.vStart, 0.0);
  for (const auto &cell : cells_.cells())
    if (cell.owned)
      for (int v = 0; v < NV; ++v) {
        if constexpr (NV == C + 1) {
          mass_[cell.vertex[v]] += dyn_.density * cell.measure / NV;
        } else {
          mass_[cell.vertex[v]] += dyn_.density * lumpedShare(cell, v);
          gravityMass_[cell.vertex[v]] += dyn_.density * consistentShare(cell, v);
        }
      }
  PetscCall(sumOverSharedVertices(mesh, 1, &mass_));
  if constexpr (NV == C + 1) gravityMass_ = mass_;
  else PetscCall(sumOverSharedVertices(mesh, 1, &gravityMass_));
  PetscFunctionReturn(0);
}

template class DiscretizationT<3, 3>;
template class DiscretizationT<2, 2>;
template class DiscretizationT<3, 2>;
template class DiscretizationT<3, 3, 8>;
template class DiscretizationT<3, 3, 10>;

}  // namespace aries::fem
