// Rest geometry: each cell's nodes and its element type's rest data (W_q, w_q, measure: kernels/elements/); one clear
// error for a degenerate or inverted rest cell; the total rest measure and the lumped vertex masses.
#include "fem/discretization_impl.hpp"

#include "core/errors.hpp"

#include <petscdmplex.h>

#include <cmath>
#include <limits>
#include <sstream>

namespace aries::fem {

using core::collectiveCheck;

template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::setupRestCells(const Mesh &mesh,
                                                     const std::vector<std::pair<DMLabel, PetscInt>> &regionLabels) {
  PetscFunctionBeginUser;
  const PetscInt nc = mesh.numCells();
  std::vector<Cell> &cells = cells_.cells();
  cells.resize(nc);
  std::vector<double> signedMeasure(nc);
  std::vector<PetscInt> corners;  // a cell's vertices
  for (PetscInt k = 0; k < nc; ++k) {
    Cell &cell = cells[k];
    PetscInt point = mesh.cStart + k;  // the DM cell whose labels give the region
    if (mesh.quadratic) {  // the element's nodes, in its own order (mesh/mesh_quadratic.cpp)
      std::copy(mesh.elementNodes[k].begin(), mesh.elementNodes[k].end(), cell.vertex.begin());
      point = mesh.elementCell[k];
    } else {  // closure order (kernels/elements/hex8.hpp for hexahedra; tetrahedra: Mesh::cellCorners where made)
      PetscCall(closureVertices(mesh, point, &corners));
      PetscCheck(corners.size() >= static_cast<std::size_t>(NV), PETSC_COMM_SELF, PETSC_ERR_PLIB,
                 "cell %" PetscInt_FMT " has %zu vertices, expected %d", point, corners.size(), NV);
      for (int v = 0; v < NV; ++v) cell.vertex[v] = corners[v];
    }
    kernels::Mat<NV, 3> X;
    for (int v = 0; v < NV; ++v) X.row(v) = verts_[cell.vertex[v]].rest.transpose();
    signedMeasure[k] = Element::rest(X, mesh.spaceDim == 3, &cell.W, &cell.weight, &cell.measure);
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
        << Element::kFoldHint
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

// Lumped mass and gravity's consistent load from every owned cell, summed over the ranks sharing a vertex: the shares
// of its rest measure the element type gives each node (kernels/elements/: measure / NV on a simplex for both).
template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::setupMass(const Mesh &mesh) {
  PetscFunctionBeginUser;
  mass_.assign(mesh.vEnd - mesh.vStart, 0.0);
  gravityMass_.assign(mesh.vEnd - mesh.vStart, 0.0);
  for (const auto &cell : cells_.cells())
    if (cell.owned)
      for (int v = 0; v < NV; ++v) {
        mass_[cell.vertex[v]] += dyn_.density * Element::lumpedShare(cell.measure, cell.weight, v);
        gravityMass_[cell.vertex[v]] += dyn_.density * Element::consistentShare(cell.measure, cell.weight, v);
      }
  PetscCall(sumOverSharedVertices(mesh, 1, &mass_));
  PetscCall(sumOverSharedVertices(mesh, 1, &gravityMass_));
  PetscFunctionReturn(0);
}

ARIES_INSTANTIATE_FOR_ELEMENT_TYPES(DiscretizationT)

}  // namespace aries::fem
