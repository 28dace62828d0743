// Mesh loading: a gmsh file read on rank 0 through DMPlex (-dm_plex_filename), partitioned with METIS (default,
// through PETSc's shell partitioner) or PT-Scotch (-partitioner ptscotch), then distributed; or the same mesh
// converted once to an HDF5 mesh (-mesh_convert, mesh/mesh_hdf5.cpp) and read by all ranks in parallel. Keeps the natural
// (serial, gmsh-order) number of every local vertex and cell, which makes random initial states, per-cell input
// files and the output independent of the number of ranks. Surface meshes (cloth, UV) are distributed with one layer
// of overlap cells so that every owned interior edge has both of its triangles locally (bending hinges); those
// overlap cells are marked not owned and are skipped by every sum over cells.
#pragma once

#include "energies/material.hpp"

#include "core/parallel.hpp"

#include <petscdmplex.h>

#include <array>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace aries::fem {

struct Mesh {
  DM dm = nullptr;  // distributed, interpolated DMPlex with coordinates and the gmsh labels
  std::string filename;
  std::string fileOption = "-dm_plex_filename";  // the option that named the file (error messages)
  energies::ElementShape shape = energies::ElementShape::Tet;  // the shape of F: 3x3 for tetrahedra and hexahedra
  bool hexahedra = false;  // trilinear hexahedra (Q1, 2x2x2 Gauss points) instead of linear tetrahedra
  // -element p2: quadratic tetrahedra (10 nodes). `dm` is then the mesh as read refined once (PETSc's regular
  // refinement, every tet into 8), so that its vertices are the P2 nodes: the corners, and one at the middle of each
  // edge of the mesh as read (natural id: the vertices' count + the edge's number in the serial mesh). Vertex-based
  // code (the section, Dirichlet sets and boxes, output, random starts) works on them unchanged; the elements are the
  // cells as read (mesh_quadratic.cpp).
  bool quadratic = false;
  std::vector<std::array<PetscInt, 10>> elementNodes;  // per element: local vertices, kernels::tet10's node order
  std::vector<PetscInt> elementCell;  // per element: one of its 8 cells in dm (its labels: the region)
  std::vector<char> edgeNode;         // per local vertex: 1 for a node at an edge's middle
  bool uvMap = false;  // -uv_map: planar elements (2D unknowns) on a 3D surface, rest = each 3D triangle
  PetscInt topoDim = 3, spaceDim = 3;
  PetscInt cStart = 0, cEnd = 0, vStart = 0, vEnd = 0;
  // Per local cell (c - cStart), or per element of a quadratic mesh:
  std::vector<PetscInt> naturalCell;
  std::vector<char> cellOwned;          // 0 for overlap cells (surface meshes carry one layer)
  std::vector<PetscInt> naturalVertex;  // per local vertex (v - vStart)
  // Tetrahedra whose faces and edges this rank made (mesh/mesh_interpolate.cpp): each cell's 4 corners as local vertices
  // (v - vStart), in its closure's order (the order they were read in); empty for any other mesh (read its closures).
  std::vector<PetscInt> cellCorners;
  PetscInt numCellsGlobal = 0, numVerticesGlobal = 0;  // elements and nodes for a quadratic mesh
  PetscInt numCells() const { return static_cast<PetscInt>(naturalCell.size()); }  // local cells (elements)
  struct PhysicalGroup {
    PetscInt dim, tag;
  };
  std::map<std::string, PhysicalGroup> physicalNames;  // gmsh $PhysicalNames
  // The cells of per-cell input files (-fiber_file, -target_file) that the local cells read: their own natural ids,
  // except on a coarse level of the nested iteration (solver/nested_start.cpp), whose cells read the run's files at
  // the cell of the run's mesh that contains their centroid.
  bool readsOtherMeshFiles = false;
  std::vector<PetscInt> fileCell;  // per local cell, where readsOtherMeshFiles
  PetscInt fileCellsGlobal = 0;    // the cells of the mesh the files belong to, where readsOtherMeshFiles
  const std::vector<PetscInt> &fileCells() const { return readsOtherMeshFiles ? fileCell : naturalCell; }
  PetscInt fileCellCount() const { return readsOtherMeshFiles ? fileCellsGlobal : numCellsGlobal; }
  Eigen::Vector3d boxMin = Eigen::Vector3d::Zero(), boxMax = Eigen::Vector3d::Zero();
  double diagonal = 1.0;  // L: bounding-box diagonal of the rest shape (paper Sec. 6)

  ~Mesh();
};

// Reads -dm_plex_filename and -partitioner; collective. A gmsh mesh (.msh) is read on rank 0 and partitioned there
// (METIS, the default, or PT-Scotch); a converted mesh (.h5, convertMesh) is read by all ranks in parallel and
// repartitioned in parallel by recursive coordinate bisection (the default; Debian's PETSc has no ParMETIS) or
// PT-Scotch. Natural ids are the gmsh order either way, so the
// results and the output files do not depend on the format.
// `file` (optional) is read instead of -dm_plex_filename (a coarse mesh of the nested iteration), and the errors about
// it name `option`.
PetscErrorCode loadMesh(MPI_Comm comm, Mesh *mesh, const std::string &file = {}, const char *option = nullptr);

// -mesh_convert OUT.h5: reads the gmsh mesh -dm_plex_filename (with the options that shape its reading:
// -dm_plex_gmsh_spacedim, -dm_plex_gmsh_use_regions) and writes its cells, coordinates and every label as arrays in the
// natural numbering (mesh/mesh_hdf5.cpp), with the physical names as root attributes aries_*. Collective.
PetscErrorCode convertMesh(MPI_Comm comm, const std::string &out);

// The vertices (local point numbers) of a gmsh physical group (closure taken). A name selects the label of its
// dimension ("Vertex Sets", "Edge Sets", "Face Sets", "Cell Sets"); a number is a boundary id, searched in
// "Face Sets", "Edge Sets" and "Vertex Sets". `found` is true if the set has points on any rank (collective).
PetscErrorCode physicalGroupVertices(const Mesh &mesh, const std::string &idOrName, std::vector<PetscInt> *vertices,
                                     bool *found);
// The facets (points of height 1: faces of a tet mesh, edges of a triangle mesh) of a physical group on this rank;
// `found` as above (the group has points of any dimension on some rank).
PetscErrorCode physicalGroupFacets(const Mesh &mesh, const std::string &idOrName, std::vector<PetscInt> *facets,
                                   bool *found);
// The facets of a physical group this rank owns (`copy`: core::sharedLeafPoints of the DM), for the option `option`
// that names it; a group not in the mesh, or without facets on any rank, is a one-line error naming the groups
// present, `purpose` saying what the option needs. Collective.
PetscErrorCode ownedGroupFacets(const Mesh &mesh, const std::vector<char> &copy, const std::string &idOrName,
                                const std::string &option, const char *purpose, std::vector<PetscInt> *owned);
// The vertices (local indices v - vStart) in the closure of a DM point (a cell, a facet), in closure order (a
// tetrahedron's from cellCorners where they were made: mesh/mesh_boundary.cpp). Not collective.
PetscErrorCode closureVertices(const Mesh &mesh, PetscInt point, std::vector<PetscInt> *vertices);

// The body's boundary facets on this rank: points of height 1 (faces of a solid, edges of a sheet or a planar mesh)
// that one cell of the whole mesh holds, every local copy (a facet of a rank's overlap cells too). Collective.
PetscErrorCode bodyBoundaryFacets(const Mesh &mesh, std::vector<PetscInt> *facets);
// Per local vertex (index v - vStart): 1 if it lies on a boundary facet (bodyBoundaryFacets), the same on every rank
// holding the vertex. Collective.
PetscErrorCode boundaryVertexFlags(const Mesh &mesh, std::vector<char> *onBoundary);

// The label and value that mark the cells of a volume group (id or name): "Cell Sets", or the group's own label
// under -dm_plex_gmsh_use_regions.
PetscErrorCode regionLabel(const Mesh &mesh, const std::string &idOrName, DMLabel *label, PetscInt *value);

// Human-readable list of the physical groups present (for error messages), collective.
PetscErrorCode describePhysicalGroups(const Mesh &mesh, std::string *text);

// Rest position of every local vertex (index v - vStart), zero-padded to 3D.
PetscErrorCode vertexRestPositions(const Mesh &mesh, std::vector<Eigen::Vector3d> *rest);

// Sums per-vertex contributions over all ranks that hold the vertex: `values` holds `ncomp` numbers per local vertex
// (index v - vStart); on return every copy holds the total. Collective.
PetscErrorCode sumOverSharedVertices(const Mesh &mesh, int ncomp, std::vector<double> *values);

}  // namespace aries::fem
