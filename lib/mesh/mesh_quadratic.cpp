// Quadratic tetrahedra (-element p2): the distributed tetrahedral mesh refined once by PETSc's regular refinement, so
// that the vertices of the refined DM are the P2 nodes (each corner, and one new vertex at the middle of each edge)
// and every vertex-based part of aries (the section and the vertex table, Dirichlet sets and boxes on the refined
// labels, output, random starts) serves the edge nodes as it serves the corners. The elements stay the cells as read:
// each lists its 10 nodes in kernels::tet10's order. Natural ids: an edge node is numbered after the vertices by its
// edge's number in the serial mesh, read on rank 0 for any number of ranks, so they do not depend on the partition.
#include "mesh/mesh_loading.hpp"

#include "core/errors.hpp"
#include "core/options.hpp"
#include "mesh/mesh_options.hpp"
#include "kernels/elements/tet10.hpp"

#include <petscdmplextransform.h>
#include <petscsf.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <string>

namespace aries::fem::loading {

PetscErrorCode chooseElement(MPI_Comm comm, DM loaded, bool hdf5, Mesh *mesh, std::vector<PetscInt> *natural,
                             PetscInt *numEdgesGlobal) {
  int choice = 0;
  PetscFunctionBeginUser;
  PetscCall(core::getChoice(opt::element, &choice));
  mesh->quadratic = core::choices(opt::element)[choice] == std::string("p2");
  *numEdgesGlobal = 0;
  if (!mesh->quadratic) PetscFunctionReturn(0);
  if (mesh->hexahedra)
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
            "option -element p2: mesh '%s' has hexahedra, which are trilinear by the mesh; p2 needs a tetrahedral "
            "mesh",
            mesh->filename.c_str());
  if (mesh->topoDim != 3)
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
            "option -element p2: quadratic elements are tetrahedra, and mesh '%s' has triangles", mesh->filename.c_str());
  if (hdf5)
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
            "option -element p2: the edge nodes are numbered on the serial gmsh mesh; '%s' is an HDF5 mesh read in "
            "parallel, give the .msh it was converted from",
            mesh->filename.c_str());
  PetscInt pStart, pEnd, eStart, eEnd;  // the serial mesh: every point on rank 0, none elsewhere
  PetscCall(DMPlexGetChart(loaded, &pStart, &pEnd));
  PetscCall(DMPlexGetDepthStratum(loaded, 1, &eStart, &eEnd));
  for (PetscInt e = eStart; e < eEnd; ++e) (*natural)[e - pStart] = mesh->numVerticesGlobal + (e - eStart);
  PetscInt count = eEnd - eStart;
  PetscCallMPI(MPI_Bcast(&count, 1, MPIU_INT, 0, comm));
  *numEdgesGlobal = count;
  PetscFunctionReturn(0);
}

PetscErrorCode placeEdgeNodes(MPI_Comm comm, DM loaded, const Mesh &mesh, const std::vector<GmshFacets::EdgeNode> &nodes,
                              std::vector<double> *edgeX) {
  PetscFunctionBeginUser;
  edgeX->clear();
  long long count = static_cast<long long>(nodes.size());  // rank 0's; none elsewhere
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &count, 1, MPI_LONG_LONG, MPI_SUM, comm));
  if (count == 0) PetscFunctionReturn(0);  // a linear file: straight edges, the nodes at the middles
  std::string error;
  PetscInt pStart, pEnd, vStart, vEnd, eStart, eEnd;
  PetscCall(DMPlexGetChart(loaded, &pStart, &pEnd));
  PetscCall(DMPlexGetDepthStratum(loaded, 0, &vStart, &vEnd));
  PetscCall(DMPlexGetDepthStratum(loaded, 1, &eStart, &eEnd));
  if (eEnd > eStart) {
    edgeX->assign(3 * (pEnd - pStart), std::nan(""));
    if (static_cast<long long>(eEnd - eStart) != count)
      error = "mesh '" + mesh.filename + "': its 10-node tetrahedra have " + std::to_string(count) +
              " distinct edge nodes for " + std::to_string(eEnd - eStart) +
              " edges; a second-order mesh has one node on every edge, shared by the tetrahedra around it";
    Vec coords;
    PetscSection section;
    const PetscScalar *x;
    PetscCall(DMGetCoordinatesLocal(loaded, &coords));
    PetscCall(DMGetCoordinateSection(loaded, &section));
    PetscCall(VecGetArrayRead(coords, &x));
    auto position = [&](PetscInt v) {
      PetscInt off;
      PetscCallAbort(PETSC_COMM_SELF, PetscSectionGetOffset(section, v, &off));
      return Eigen::Vector3d(x[off], x[off + 1], x[off + 2]);
    };
    auto point = [](const Eigen::Vector3d &p) {
      std::ostringstream o;
      o << "(" << p[0] << ", " << p[1] << ", " << p[2] << ")";
      return o.str();
    };
    for (PetscInt e = eStart; e < eEnd && error.empty(); ++e) {
      const PetscInt *cone;
      PetscCall(DMPlexGetCone(loaded, e, &cone));
      const long a = std::min(cone[0], cone[1]) - vStart, b = std::max(cone[0], cone[1]) - vStart;
      const auto found = std::lower_bound(nodes.begin(), nodes.end(), std::make_pair(a, b),
                                          [](const GmshFacets::EdgeNode &n, const std::pair<long, long> &k) {
                                            return n.a != k.first ? n.a < k.first : n.b < k.second;
                                          });
      const Eigen::Vector3d A = position(cone[0]), B = position(cone[1]);
      if (found == nodes.end() || found->a != a || found->b != b) {
        error = "mesh '" + mesh.filename + "': the edge from " + point(A) + " to " + point(B) +
                " has no node in the file's 10-node tetrahedra";
        break;
      }
      const Eigen::Vector3d node(found->x[0], found->x[1], found->x[2]);
      // A curved edge's node lies near its middle (a quarter circle's: 0.21 of the chord away); one far off means a
      // node order aries does not read (gmsh's: nodes 4-9 on edges 01, 12, 02, 03, 23, 13).
      if ((node - 0.5 * (A + B)).norm() > 0.25 * (B - A).norm()) {
        std::ostringstream off;
        off << (node - 0.5 * (A + B)).norm() / (B - A).norm();
        error = "mesh '" + mesh.filename + "': the edge node at " + point(node) + " lies " + off.str() +
                " edge lengths from the middle of its edge " + point(A) + " - " + point(B) +
                " (more than 0.25); the 10-node tetrahedra must list their nodes in gmsh's order";
        break;
      }
      for (int d = 0; d < 3; ++d) (*edgeX)[3 * (e - pStart) + d] = node[d];
    }
    PetscCall(VecRestoreArrayRead(coords, &x));
  }
  PetscCall(core::collectiveCheck(comm, !error.empty(), error));
  PetscFunctionReturn(0);
}

PetscErrorCode migrateEdgeNodes(PetscSF migration, const std::vector<double> &loaded, DM dm, std::vector<double> *local) {
  PetscFunctionBeginUser;
  local->clear();
  int any = !loaded.empty();
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &any, 1, MPI_INT, MPI_MAX, PetscObjectComm((PetscObject)dm)));
  if (!any) PetscFunctionReturn(0);
  PetscInt pStart, pEnd;
  PetscCall(DMPlexGetChart(dm, &pStart, &pEnd));
  if (!migration) {  // one rank: the loaded mesh is the mesh
    *local = loaded;
    PetscFunctionReturn(0);
  }
  local->assign(3 * (pEnd - pStart), std::nan(""));
  MPI_Datatype triple;
  PetscCallMPI(MPI_Type_contiguous(3, MPI_DOUBLE, &triple));
  PetscCallMPI(MPI_Type_commit(&triple));
  PetscCall(PetscSFBcastBegin(migration, triple, loaded.data(), local->data(), MPI_REPLACE));
  PetscCall(PetscSFBcastEnd(migration, triple, loaded.data(), local->data(), MPI_REPLACE));
  PetscCallMPI(MPI_Type_free(&triple));
  PetscFunctionReturn(0);
}

namespace {

// The 10 nodes of cell c of the unrefined mesh as vertices of the refined one (local indices): its corners in closure
// order, then the middle of each edge kEdges[k], found among the cell's edges by their cones.
PetscErrorCode elementNodes(DM coarse, DMPlexTransform tr, PetscInt c, PetscInt fineVStart,
                            std::array<PetscInt, 10> *nodes) {
  PetscInt ncl, *closure = nullptr, vStart, vEnd, eStart, eEnd;
  PetscInt corners[4], edges[6], nc = 0, ne = 0;
  PetscFunctionBeginUser;
  PetscCall(DMPlexGetDepthStratum(coarse, 0, &vStart, &vEnd));
  PetscCall(DMPlexGetDepthStratum(coarse, 1, &eStart, &eEnd));
  PetscCall(DMPlexGetTransitiveClosure(coarse, c, PETSC_TRUE, &ncl, &closure));
  for (PetscInt i = 0; i < ncl; ++i) {
    const PetscInt p = closure[2 * i];
    if (p >= vStart && p < vEnd && nc < 4) corners[nc++] = p;
    if (p >= eStart && p < eEnd && ne < 6) edges[ne++] = p;
  }
  PetscCall(DMPlexRestoreTransitiveClosure(coarse, c, PETSC_TRUE, &ncl, &closure));
  PetscCheck(nc == 4 && ne == 6, PETSC_COMM_SELF, PETSC_ERR_PLIB, "cell %d: %d corners and %d edges, not a tetrahedron",
             (int)c, (int)nc, (int)ne);
  for (int k = 0; k < 4; ++k) {
    PetscInt fine;
    PetscCall(DMPlexTransformGetTargetPoint(tr, DM_POLYTOPE_POINT, DM_POLYTOPE_POINT, corners[k], 0, &fine));
    (*nodes)[k] = fine - fineVStart;
  }
  for (int k = 0; k < 6; ++k) {
    const PetscInt a = corners[kernels::tet10::kEdges[k][0]], b = corners[kernels::tet10::kEdges[k][1]];
    PetscInt edge = -1;
    for (PetscInt e : edges) {
      const PetscInt *cone;
      PetscCall(DMPlexGetCone(coarse, e, &cone));
      if ((cone[0] == a && cone[1] == b) || (cone[0] == b && cone[1] == a)) edge = e;
    }
    PetscCheck(edge >= 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "cell %d: no edge joins two of its corners", (int)c);
    PetscInt fine;
    PetscCall(DMPlexTransformGetTargetPoint(tr, DM_POLYTOPE_SEGMENT, DM_POLYTOPE_POINT, edge, 0, &fine));
    (*nodes)[4 + k] = fine - fineVStart;
  }
  PetscFunctionReturn(0);
}

// DMPlex's closure order gives its tetrahedra the negative orientation; VTK's Tetrahedron_10 (and ParaView's
// higher-order rendering) expects corners 1, 2, 3 counterclockwise seen from corner 0. When the majority of the mesh's
// elements is negative, every element's corners 1 and 2 swap, with the edge nodes that follow them; an element
// oriented against the majority stays so, for the rest-cell check to report it.
PetscErrorCode orientElements(Mesh *mesh) {
  std::vector<Eigen::Vector3d> rest;
  PetscFunctionBeginUser;
  PetscCall(vertexRestPositions(*mesh, &rest));
  PetscInt negative[2] = {0, 0};  // negative, all
  for (const auto &n : mesh->elementNodes) {
    const double volume = (rest[n[1]] - rest[n[0]]).cross(rest[n[2]] - rest[n[0]]).dot(rest[n[3]] - rest[n[0]]);
    negative[0] += volume < 0.0;
    negative[1] += 1;
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, negative, 2, MPIU_INT, MPI_SUM, PetscObjectComm((PetscObject)mesh->dm)));
  if (2 * negative[0] <= negative[1]) PetscFunctionReturn(0);
  constexpr int swapped[10] = {0, 2, 1, 3, 6, 5, 4, 7, 9, 8};  // corners 1 <-> 2: edges 01 <-> 02, 13 <-> 23
  for (auto &n : mesh->elementNodes) {
    const std::array<PetscInt, 10> old = n;
    for (int k = 0; k < 10; ++k) n[k] = old[swapped[k]];
  }
  PetscFunctionReturn(0);
}

}  // namespace

PetscErrorCode refineToQuadratic(Mesh *mesh, const std::vector<PetscInt> &pointNatural, PetscInt numEdgesGlobal,
                                 const std::vector<double> &pointEdgeX) {
  DM coarse = mesh->dm, fine = nullptr;
  DMPlexTransform tr;
  PetscInt pStart, pEnd, vStart, vEnd, cStart, cEnd;
  PetscFunctionBeginUser;
  const MPI_Comm comm = PetscObjectComm((PetscObject)coarse);
  PetscCall(DMPlexGetChart(coarse, &pStart, &pEnd));
  PetscCall(DMPlexTransformCreate(comm, &tr));
  PetscCall(DMPlexTransformSetDM(tr, coarse));
  PetscCall(DMPlexTransformSetType(tr, DMPLEXREFINEREGULAR));
  PetscCall(DMPlexTransformSetUp(tr));
  PetscCall(DMPlexTransformApply(tr, coarse, &fine));  // coordinates (edge nodes at the middles), labels, point SF
  PetscCall(DMPlexGetDepthStratum(fine, 0, &vStart, &vEnd));
  PetscCall(DMPlexGetHeightStratum(fine, 0, &cStart, &cEnd));

  std::vector<PetscInt> naturalVertex(vEnd - vStart, -1);
  mesh->edgeNode.assign(vEnd - vStart, 0);
  Vec coords = nullptr;
  PetscSection coordSection = nullptr;
  PetscScalar *x = nullptr;
  if (!pointEdgeX.empty()) {  // a second-order file: its (curved) edge nodes replace the middles
    PetscCall(DMGetCoordinatesLocal(fine, &coords));
    PetscCall(DMGetCoordinateSection(fine, &coordSection));
    PetscCall(VecGetArray(coords, &x));
  }
  for (PetscInt v = vStart; v < vEnd; ++v) {
    DMPolytopeType source, target;
    PetscInt p, r;
    PetscCall(DMPlexTransformGetSourcePoint(tr, v, &source, &target, &p, &r));
    naturalVertex[v - vStart] = pointNatural[p - pStart];
    mesh->edgeNode[v - vStart] = source == DM_POLYTOPE_SEGMENT;
    PetscCheck(naturalVertex[v - vStart] >= 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "refined vertex %d has no natural id",
               (int)v);
    if (x && source == DM_POLYTOPE_SEGMENT) {
      const double *node = &pointEdgeX[3 * (p - pStart)];
      PetscCheck(std::isfinite(node[0]), PETSC_COMM_SELF, PETSC_ERR_PLIB, "edge %d has no node position", (int)p);
      PetscInt off;
      PetscCall(PetscSectionGetOffset(coordSection, v, &off));
      for (int d = 0; d < 3; ++d) x[off + d] = node[d];
    }
  }
  if (x) {
    PetscCall(VecRestoreArray(coords, &x));
    PetscCall(DMSetCoordinatesLocal(fine, coords));  // drops the global coordinates made from the middles
  }
  const PetscInt numElements = mesh->cEnd - mesh->cStart;
  mesh->elementNodes.resize(numElements);
  mesh->elementCell.resize(numElements);
  for (PetscInt c = mesh->cStart; c < mesh->cEnd; ++c) {
    PetscCall(elementNodes(coarse, tr, c, vStart, &mesh->elementNodes[c - mesh->cStart]));
    PetscCall(DMPlexTransformGetTargetPoint(tr, DM_POLYTOPE_TETRAHEDRON, DM_POLYTOPE_TETRAHEDRON, c, 0,
                                            &mesh->elementCell[c - mesh->cStart]));
  }
  PetscCall(DMPlexTransformDestroy(&tr));
  PetscCall(DMDestroy(&mesh->dm));
  mesh->dm = fine;
  mesh->cellCorners.clear();  // the fine mesh's cells are not the ones read (closureVertices reads their closures)
  PetscCall(PetscObjectSetName((PetscObject)mesh->dm, "aries_mesh"));
  mesh->cStart = cStart, mesh->cEnd = cEnd, mesh->vStart = vStart, mesh->vEnd = vEnd;
  mesh->naturalVertex = std::move(naturalVertex);
  mesh->numVerticesGlobal += numEdgesGlobal;  // naturalCell, cellOwned and numCellsGlobal stay per element
  PetscCall(orientElements(mesh));
  PetscFunctionReturn(0);
}

}  // namespace aries::fem::loading
