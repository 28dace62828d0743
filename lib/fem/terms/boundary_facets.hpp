// The facets of a boundary group with their vertices ordered so that the kernels' normal points out of the body: on
// a triangle (x1 - x0) x (x2 - x0), on a quadrangle (vertices cyclic) (x2 - x0) x (x3 - x1), on an edge of a planar mesh
// (x, y plane) the tangent x1 - x0 turned clockwise, (t_y, -t_x). Surface loads and pressures both start from these.
#pragma once

#include "mesh/mesh.hpp"
#include "fem/vertex_layout.hpp"

#include <array>
#include <string>
#include <vector>

namespace aries::fem {

struct OrientedFacet {
  std::array<PetscInt, 4> vertex{-1, -1, -1, -1};  // local vertex indices, outward order
  int count = 0;                                    // 2 (edge), 3 (triangle) or 4 (quadrangle)
  PetscInt cell = -1;                               // the one cell it bounds (DM point)
};

// Orients each of `facets` (DM points of height 1) by the cell it bounds: the normal points away from that cell's
// centroid. A facet bounding two cells (inside the body) is a one-line error naming `option`. Not collective.
PetscErrorCode orientBoundaryFacets(const Mesh &mesh, const VertexTable &verts, const std::vector<PetscInt> &facets,
                                    const std::string &option, std::vector<OrientedFacet> *oriented);

// The faces of a quadratic tetrahedral mesh (-element p2) that a group covers: the refined DM's boundary triangles
// come 4 to a face, and each face of an element whose 3 edge nodes make one of the group's middle triangles (among
// `facets`, this rank's) is a face of the group: 6 local vertices in kernels::face::Tri6's order (corners, then the
// nodes on edges 01, 12, 20), outward (the corners' plane's normal away from the element's fourth corner; the face
// itself may be curved). A middle triangle that is no element's face, or two elements', is a one-line error naming
// `option`. Not collective.
PetscErrorCode quadraticGroupFaces(const Mesh &mesh, const VertexTable &verts, const std::vector<PetscInt> &facets,
                                   const std::string &option, std::vector<std::array<PetscInt, 6>> *faces);

// The facet's outward normal times its rest area (length for an edge), by the rule above for a quadrangle: the area
// vector of the flat facet, or of a warped quadrangle's bilinear patch.
Eigen::Vector3d restAreaVector(const VertexTable &verts, const OrientedFacet &f);

}  // namespace aries::fem
