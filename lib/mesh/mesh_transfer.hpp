// Interpolation between two tetrahedral meshes of the same body that need not be nested (a coarse mesh generated from
// the same surface at a larger size): each vertex of the target mesh is located once in the rest shape of the source
// mesh, and a field given at the source's vertices is then evaluated there with the linear shape functions of the
// cell found (its barycentric coordinates), at every local vertex of the target (ghosts included). Used by the nested
// iteration (solver/nested_start.cpp) in both directions: coarse -> fine for the start of a fine solve, fine -> coarse
// for the state a coarse solve starts from.
//
// Location: a target vertex inside source cells takes the one with the smallest natural id among those containing it
// (up to round-off); a vertex outside the source mesh (a fine surface vertex beyond a coarse facet) takes the cell
// nearest to it, and the field is extrapolated linearly from that cell, so a linear field is reproduced exactly at every
// vertex. Every rank locates its points among its own cells only: a point is sent to each rank whose cells, enlarged by
// the largest source cell's diameter, contain it, and every candidate cell is judged by a rule that does not depend on
// the partition, so the weights (and hence every interpolated value) are the same on any number of ranks. A target
// vertex farther than that diameter from every source cell is an error (the meshes are not of the same body). No rank
// holds more than its own cells and the points sent to it.
#pragma once

#include "core/parallel.hpp"
#include "mesh/mesh.hpp"

#include <array>
#include <string>
#include <vector>

namespace aries::fem {

class VertexInterpolation {
 public:
  // Locates the local vertices of `target` in `source` (both tetrahedral, distributed on the same communicator).
  // `what` names the pair in the error message of a vertex outside the source ("-coarse_mesh 'a.msh' for 'b.msh'").
  // Collective.
  PetscErrorCode setup(const Mesh &source, const Mesh &target, const std::string &what);
  // `sourceValues`: 3 values per local source vertex (index v - vStart, every local vertex, ghosts included). On
  // return `targetValues` holds the interpolated field, 3 values per local target vertex. Collective.
  PetscErrorCode interpolate(const std::vector<double> &sourceValues, std::vector<double> *targetValues) const;
  // Largest distance of a target vertex outside the source mesh to the cell it was extrapolated from (0 when the
  // source covers every target vertex); global.
  double largestOutsideDistance() const { return outside_; }

 private:
  core::RowRoute route_;                          // local target vertex k -> the rank whose cell holds it
  std::vector<std::array<PetscInt, 4>> corner_;   // per received row: the source cell's local vertices
  std::vector<std::array<double, 4>> weight_;     // and their barycentric weights
  double outside_ = 0.0;
};

// For each of `points` (rest positions, this rank's list), the value `cellValues` gives (one per local cell of
// `source`, index c - cStart) to the source cell that contains the point, or the nearest one; chosen as
// VertexInterpolation chooses, the same on any number of ranks. A point farther than the largest source cell from
// every one is an error naming `what` and the two meshes (`target`: where the points come from). Collective.
PetscErrorCode valuesOfCellsAt(const Mesh &source, const std::vector<PetscInt> &cellValues, const Mesh &target,
                               const std::vector<Eigen::Vector3d> &points, const std::string &what,
                               std::vector<PetscInt> *values);

}  // namespace aries::fem
