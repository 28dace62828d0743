// The elastic energy of the cells: sum over owned cells and their quadrature points q of w_q Psi(F_q), F_q = sum_v x_v
// W_q.row(v) (kernels/element_rules.hpp; W_q and w_q from the element type, kernels/elements/), with the material of
// the cell's region (energies/energy.hpp): one point for linear simplices (W = [-1^T Dm^-1; Dm^-1], w = the rest
// measure), 2x2x2 Gauss points for trilinear hexahedra, 4 points for quadratic tetrahedra (whose 10 nodes are vertices
// of the refined mesh, mesh/mesh_quadratic.cpp). The Hessian is eigenvalue-filtered per point. Owns the per-cell rest
// data (vertices, W_q, w_q, measure, region) and the anisotropy data (per cell: every point of a cell has its cell's
// fibers, target and curvature), and the barrier mode's per-cell fallback to the mollifier (a cell falls back when any
// of its points is singular).
#pragma once

#include "fem/terms/element_scatter.hpp"
#include "fem/terms/term.hpp"
#include "fem/vertex_layout.hpp"
#include "fem/element_types.hpp"
#include "kernels/element_rules.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace aries::fem {

template <int R, int C, int NV = C + 1>  // NV: nodes per cell (C + 1: linear simplex; 8: trilinear hexahedron; 10: P2)
class ElasticCells final : public Term {
 public:
  static constexpr int NQ = kernels::ElementOf<R, C, NV>::NQ;  // quadrature points per cell
  static constexpr int NDOF = NV * R;
  static constexpr int NF = R * C;   // entries of F
  struct Cell {
    std::array<PetscInt, NV> vertex;           // local vertex index (v - vStart), DMPlex closure order
    std::array<kernels::Mat<NV, C>, NQ> W;     // F_q = sum_v x_v W[q].row(v)
    std::array<double, NQ> weight;             // rest measure carried by point q (sums to measure)
    double measure;                            // rest volume / area
    int region;                       // material index
    bool owned;                       // false for overlap cells (surface meshes), skipped by all sums
  };

  ElasticCells(const VertexTable &verts, const std::vector<energies::Material> &materials)
      : verts_(verts), materials_(materials) {}
  const char *name() const override { return "elastic cells"; }
  void addEnergy(const PetscScalar *x, double *energy, double *magnitude) const override;
  void addGradient(const PetscScalar *x, PetscScalar *g) const override;
  PetscErrorCode addHessian(const PetscScalar *x, const HessianAssembly &how, Mat J) const override;
  void addCurvature(const PetscScalar *x, const PetscScalar *const d[], int K, GramMatrix *q) const override;
  PetscInt offRankHessianValues() const override;

  std::vector<Cell> &cells() { return cells_; }
  const std::vector<Cell> &cells() const { return cells_; }
  size_t size() const { return cells_.size(); }
  // Anisotropy data: one entry shared by all cells, or one per cell.
  std::vector<energies::CellData<C>> &cellData() { return cellData_; }
  const std::vector<energies::CellData<C>> &cellData() const { return cellData_; }
  bool dataShared() const { return cellData_.size() == 1; }
  const energies::CellData<C> &dataOf(size_t c) const { return cellData_.size() == 1 ? cellData_[0] : cellData_[c]; }
  // The material a cell is evaluated with: its region's, or the mollified copy where the barrier fell back.
  const energies::Material &materialOf(size_t c) const {
    return fallback_.empty() || !fallback_[c] ? materials_[cells_[c].region] : mollified_[cells_[c].region];
  }
  // F at point q of cell c.
  kernels::Mat<R, C> deformationGradient(size_t c, int q, const PetscScalar *x) const {
    const Cell &cell = cells_[c];
    kernels::Mat<R, C> F = kernels::Mat<R, C>::Zero();
    for (int v = 0; v < NV; ++v) {
      const PetscScalar *xv = x + verts_[cell.vertex[v]].loc;
      for (int i = 0; i < R; ++i) F.row(i) += xv[i] * cell.W[q].row(v);
    }
    return F;
  }
  // Psi averaged over the cell (sum_q w_q Psi(F_q) / measure).
  double energyDensity(size_t c, const PetscScalar *x) const {
    auto psi = [&](int q) {
      return energies::evaluateEnergy<R, C>(materialOf(c), dataOf(c), deformationGradient(c, q, x),
                                            kernels::Order::Value).value;
    };
    if constexpr (NQ == 1) return psi(0);
    double e = 0.0;
    for (int q = 0; q < NQ; ++q) e += cells_[c].weight[q] * psi(q);
    return e / cells_[c].measure;
  }
  // The smallest alpha over the cell's points (the barrier fallback's per-cell measure and the output's); NaN if any
  // point's is (a non-finite state: the safeguard's test). The guard below, exact everywhere.
  double alpha(size_t c, const PetscScalar *x) const { return guard(c, x, std::numeric_limits<double>::infinity()); }
  // The safeguard's guard value: the cell's alpha where it is below `exactBelow`, elsewhere some value in [exactBelow,
  // alpha], so a test of it against any threshold up to exactBelow reads as the same test of alpha. A 3x3 point
  // whose alphaLowerBound (64 J, kernels/root_function.hpp) clears exactBelow needs no root: cells near their rest
  // shape, most of any scene, cost a determinant instead of the root's Newton iteration. NaN if any point's alpha is;
  // a non-finite bound takes the root.
  double guard(size_t c, const PetscScalar *x, double exactBelow) const {
    double g = std::numeric_limits<double>::infinity();
    for (int q = 0; q < NQ; ++q) {
      const kernels::Mat<R, C> F = deformationGradient(c, q, x);
      double gq;
      if constexpr (R == 3 && C == 3) {
        const double bound = kernels::alphaLowerBound(F);
        gq = (bound >= exactBelow && std::isfinite(bound)) ? bound : energies::elementAlpha<R, C>(F);
      } else {
        gq = energies::elementAlpha<R, C>(F);
      }
      if (std::isnan(gq)) return gq;
      g = std::min(g, gq);
    }
    return g;
  }
  // A local solve's focus (Discretization::setFocus): only the owned cells with a vertex in `vertexMask` (per local
  // vertex) are summed by addEnergy, addGradient, addHessian and addCurvature; nullptr: every owned cell again.
  void setFocus(const std::vector<char> *vertexMask) {
    focused_ = vertexMask != nullptr;
    focus_.clear();
    if (!focused_) return;
    for (size_t c = 0; c < cells_.size(); ++c) {
      if (!cells_[c].owned) continue;
      for (int v = 0; v < NV; ++v)
        if ((*vertexMask)[cells_[c].vertex[v]]) {
          focus_.push_back(c);
          break;
        }
    }
  }
  bool focused() const { return focused_; }
  const std::vector<size_t> &focus() const { return focus_; }
  // Calls f(c) for every owned cell, or for the focus's cells while one is set.
  template <class F>
  void forEachOwnedCell(F &&f) const {
    if (focused_) {
      for (size_t c : focus_) f(c);
      return;
    }
    for (size_t c = 0; c < cells_.size(); ++c)
      if (cells_[c].owned) f(c);
  }
  // Barrier mode at singular elements (paper Sec. 7.1): cells with alpha <= threshold are evaluated with the
  // mollifier until a later call finds them above it. Returns the number of such local cells.
  PetscInt updateBarrierFallback(const std::vector<double> &alpha, double threshold);

 private:
  const VertexTable &verts_;
  const std::vector<energies::Material> &materials_;
  std::vector<Cell> cells_;
  std::vector<energies::CellData<C>> cellData_;
  std::vector<char> fallback_;                 // per cell: barrier -> mollifier
  std::vector<energies::Material> mollified_;  // materials_ with the barrier replaced by the mollifier
  mutable ElementScatter<NV, R> scatter_;      // where each cell's blocks go in the last Hessian matrix's arrays
  bool focused_ = false;
  std::vector<size_t> focus_;  // the focus's owned cells (setFocus)
};

}  // namespace aries::fem
