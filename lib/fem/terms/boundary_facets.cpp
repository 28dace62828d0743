#include "fem/terms/boundary_facets.hpp"

#include "kernels/elements/tet10.hpp"

#include <algorithm>
#include <map>
#include <utility>

namespace aries::fem {

namespace {

Eigen::Vector3d kernelNormal(const VertexTable &verts, const OrientedFacet &f) {
  const Eigen::Vector3d &X0 = verts[f.vertex[0]].rest, &X1 = verts[f.vertex[1]].rest;
  if (f.count == 2) return Eigen::Vector3d(X1[1] - X0[1], -(X1[0] - X0[0]), 0.0);
  const Eigen::Vector3d &X2 = verts[f.vertex[2]].rest;
  if (f.count == 3) return (X1 - X0).cross(X2 - X0);
  return (X2 - X0).cross(verts[f.vertex[3]].rest - X1);
}

}  // namespace

Eigen::Vector3d restAreaVector(const VertexTable &verts, const OrientedFacet &f) {
  const Eigen::Vector3d n = kernelNormal(verts, f);
  return f.count == 2 ? n : Eigen::Vector3d(0.5 * n);
}

PetscErrorCode orientBoundaryFacets(const Mesh &mesh, const VertexTable &verts, const std::vector<PetscInt> &facets,
                                    const std::string &option, std::vector<OrientedFacet> *oriented) {
  PetscFunctionBeginUser;
  oriented->clear();
  for (PetscInt point : facets) {
    PetscInt ns;
    const PetscInt *supp;
    std::vector<PetscInt> vs, cell;
    PetscCall(DMPlexGetSupportSize(mesh.dm, point, &ns));
    PetscCall(DMPlexGetSupport(mesh.dm, point, &supp));
    if (ns != 1)
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
              "option %s: the group has a facet inside the body (between two cells); a load acts on boundary facets",
              option.c_str());
    PetscCall(closureVertices(mesh, point, &vs));
    if (vs.size() < 2 || vs.size() > 4)
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_SUP, "option %s: a facet with %d vertices", option.c_str(), (int)vs.size());
    OrientedFacet f;
    f.count = static_cast<int>(vs.size());
    f.cell = supp[0];
    std::copy(vs.begin(), vs.end(), f.vertex.begin());
    if (f.count == 4) {
      // Cyclic order: of the three ways to pair the corners as diagonals, the one whose diagonals' cross product is
      // largest (a quadrangle's diagonals cross; a wrong order makes one "diagonal" a side).
      const std::array<std::array<int, 4>, 3> orders = {{{0, 1, 2, 3}, {0, 1, 3, 2}, {0, 2, 1, 3}}};
      double best = -1.0;
      std::array<PetscInt, 4> cyclic = f.vertex;
      for (const auto &o : orders) {
        const double a = (verts[vs[o[2]]].rest - verts[vs[o[0]]].rest)
                             .cross(verts[vs[o[3]]].rest - verts[vs[o[1]]].rest)
                             .norm();
        if (a > best) {
          best = a;
          for (int k = 0; k < 4; ++k) cyclic[k] = vs[o[k]];
        }
      }
      f.vertex = cyclic;
    }
    PetscCall(closureVertices(mesh, f.cell, &cell));
    Eigen::Vector3d inner = Eigen::Vector3d::Zero();
    for (PetscInt v : cell) inner += verts[v].rest / static_cast<double>(cell.size());
    if (kernelNormal(verts, f).dot(inner - verts[f.vertex[0]].rest) > 0.0) {
      if (f.count == 2) std::swap(f.vertex[0], f.vertex[1]);
      else if (f.count == 3) std::swap(f.vertex[1], f.vertex[2]);
      else std::swap(f.vertex[1], f.vertex[3]);  // reverses the cycle, keeps it cyclic
    }
    oriented->push_back(f);
  }
  PetscFunctionReturn(0);
}

PetscErrorCode quadraticGroupFaces(const Mesh &mesh, const VertexTable &verts, const std::vector<PetscInt> &facets,
                                   const std::string &option, std::vector<std::array<PetscInt, 6>> *faces) {
  using Key = std::array<PetscInt, 3>;
  PetscFunctionBeginUser;
  faces->clear();
  std::map<Key, int> middles;  // the group's middle triangles (3 edge nodes), sorted vertices -> times matched
  for (PetscInt f : facets) {
    std::vector<PetscInt> vs;
    PetscCall(closureVertices(mesh, f, &vs));
    if (vs.size() == 3 && mesh.edgeNode[vs[0]] && mesh.edgeNode[vs[1]] && mesh.edgeNode[vs[2]]) {
      Key k = {vs[0], vs[1], vs[2]};
      std::sort(k.begin(), k.end());
      middles[k] = 0;
    }
  }
  namespace t10 = kernels::tet10;
  auto edgeOf = [](int a, int b) {
    for (int e = 0; e < 6; ++e)
      if ((t10::kEdges[e][0] == a && t10::kEdges[e][1] == b) || (t10::kEdges[e][0] == b && t10::kEdges[e][1] == a))
        return 4 + e;
    return -1;
  };
  for (const auto &nodes : mesh.elementNodes)
    for (int opposite = 0; opposite < 4; ++opposite) {
      int c[3], n = 0;
      for (int k = 0; k < 4; ++k)
        if (k != opposite) c[n++] = k;
      const Key key = {nodes[edgeOf(c[0], c[1])], nodes[edgeOf(c[1], c[2])], nodes[edgeOf(c[2], c[0])]};
      Key sorted = key;
      std::sort(sorted.begin(), sorted.end());
      auto it = middles.find(sorted);
      if (it == middles.end()) continue;
      ++it->second;
      std::array<PetscInt, 6> face = {nodes[c[0]], nodes[c[1]], nodes[c[2]], key[0], key[1], key[2]};
      const Eigen::Vector3d &X0 = verts[face[0]].rest;
      const Eigen::Vector3d normal = (verts[face[1]].rest - X0).cross(verts[face[2]].rest - X0);
      if (normal.dot(verts[nodes[opposite]].rest - X0) > 0.0) {
        std::swap(face[1], face[2]);  // corners 1, 2 swap; the edges 01 and 20 swap with them
        std::swap(face[3], face[5]);
      }
      faces->push_back(face);
    }
  for (const auto &kv : middles)
    if (kv.second != 1)
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
              "option %s: the group has a face that is %s of the quadratic elements (a load acts on boundary faces)",
              option.c_str(), kv.second == 0 ? "no face" : "a face of two");
  PetscFunctionReturn(0);
}

}  // namespace aries::fem
