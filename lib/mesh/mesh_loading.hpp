// The pieces of mesh loading (mesh/mesh.hpp) shared by its files: the gmsh reader (mesh.cpp), the HDF5 reader and
// converter (mesh_hdf5.cpp) and the partitioners (mesh_partition.cpp). Internal to lib/fem.
#pragma once

#include "mesh/gmsh_check.hpp"
#include "mesh/mesh.hpp"

#include <metis.h>

#include <map>
#include <string>
#include <vector>

namespace aries::fem::loading {

// The element shape from the cell and space dimensions (-uv_map: triangles in 3D with 2D unknowns).
PetscErrorCode classifyShape(const GmshFacts &facts, Mesh *mesh);
// The cells' polytope (mesh->hexahedra): one type, tetrahedra, triangles or hexahedra; collective.
PetscErrorCode classifyCells(DM dm, Mesh *mesh);
// "dim tag name" lines (rank 0's blob, broadcast) parsed into the mesh's physical names.
PetscErrorCode parsePhysicalNames(MPI_Comm comm, std::string blob, std::map<std::string, Mesh::PhysicalGroup> *names);
// The gmsh file -dm_plex_filename read on rank 0: its serial DM, the natural id of every point of its chart (cell or
// vertex number, -1 for others), the physical names and the global counts. With mayDeferFaces, a mesh whose faces and
// edges can be made after distribution (-mesh_faces) is read as cells and vertices only (*deferred): facetRows (rank
// 0) then holds its tagged faces ("Face Sets" rows for labelDeferredRows).
// edgeNodes (rank 0, optional): the edge nodes of the file's 10-node tetrahedra (GmshFacets::edgeNodes).
PetscErrorCode readGmshMesh(MPI_Comm comm, Mesh *mesh, DM *serial, std::vector<PetscInt> *natural, bool mayDeferFaces,
                            bool *deferred, std::vector<long long> *facetRows,
                            std::vector<GmshFacets::EdgeNode> *edgeNodes = nullptr);
// PETSc's gmsh reader on rank 0 (mesh/mesh_facets.cpp): a 3D mesh whose tagged faces `facets` holds (and PETSc's
// default gmsh labels) as cells and vertices only, when mayDeferFaces (*deferred; facetRows: rank 0's rows of its tagged
// faces); any other mesh with its faces and edges. Collective.
PetscErrorCode readGmshSerial(MPI_Comm comm, const Mesh &mesh, const GmshFacets &facets, bool mayDeferFaces,
                              DM *serial, bool *deferred, std::vector<long long> *facetRows);
// Label rows on the faces and edges of a 3D mesh read as cells and vertices only (-mesh_faces distributed), kept until
// every rank has made the faces and edges of its part: per label name, rows of kPointLabelCols whose first entry is
// the natural id of a cell, held by the rank whose loaded mesh has that cell.
struct DeferredLabelRows {
  std::vector<std::string> names;
  std::vector<std::vector<long long>> rows;  // per name
};
// Collective: the rows moved with their cells when the loaded mesh was distributed (migration: leaf a distributed
// point, root the loaded point it came from; none on one rank, the rows stay). No rank receives other ranks' rows.
PetscErrorCode routeDeferredRows(MPI_Comm comm, PetscSF migration, DM loaded, const std::vector<PetscInt> &loadedNatural,
                                 DeferredLabelRows *deferred);
// Collective: the labels of the distributed, interpolated mesh->dm from this rank's routed rows (natural ids:
// mesh->naturalCell and naturalVertex must be set); a label with no row anywhere is not made.
PetscErrorCode labelDeferredRows(MPI_Comm comm, Mesh *mesh, const DeferredLabelRows &deferred);
bool isHdf5Mesh(const std::string &file);
// A mesh converted by convertMesh, read by all ranks in parallel; `natural` as for readGmshMesh, per loaded point.
// With mayDeferFaces a 3D mesh is built as cells and vertices only (*deferred): its labels' face and edge rows are
// then left in *deferredRows (this rank's block), its cell and vertex rows applied.
PetscErrorCode readHdf5Mesh(MPI_Comm comm, Mesh *mesh, DM *dm, std::vector<PetscInt> *natural, bool mayDeferFaces,
                            bool *deferred, DeferredLabelRows *deferredRows);
// Label rows on faces, edges and vertices (the HDF5 mesh format, and the facets of a gmsh mesh interpolated after it
// is distributed): one row per (point, cell that contains it): the cell's id, the point's dimension, the label value
// and the point's vertex ids (natural, sorted, the first three, -1 padded). Three ids name a face of a hexahedron too.
constexpr int kPointLabelCols = 6;
// Vertices of point p in its closure order, as natural ids (vertexNatural[v - vStart]).
PetscErrorCode closureVertices(DM dm, PetscInt p, PetscInt vStart, PetscInt vEnd, const PetscInt *vertexNatural,
                               std::vector<long long> *ids);
// Labels this rank's copies of the rows' points: each row names a local cell (its id minus firstCell: the index among
// the local cells), itself (cell rows: cols 2) or the point of its closure with the row's dimension and vertices (cols
// kPointLabelCols); ok turns false for a row that names no local cell or no such point.
PetscErrorCode applyLabelRows(DM dm, DMLabel label, const std::vector<long long> &rows, int cols, PetscInt firstCell,
                              const PetscInt *vertexNatural, bool *ok);

// DMPlexInterpolate's result (faces and edges, point SF, coordinates, labels), made in one pass for a 3D mesh of
// tetrahedra (mesh/mesh_interpolate.cpp); any other mesh is handed to DMPlexInterpolate. corners (optional): for the
// tetrahedra, each cell's 4 corners as local vertices (Mesh::cellCorners), else emptied. Collective.
PetscErrorCode interpolateMesh(DM dm, DM *interpolated, std::vector<PetscInt> *corners = nullptr);

// The dual graph of the cells of a mesh held as cells and vertices (rank 0 may hold all of it, the others none), in
// METIS's index type: cells are neighbours when they share a face's number of corners (METIS_MeshToDual's graph), each
// cell's neighbours in increasing order (mesh/mesh_partition.cpp).
PetscErrorCode cellDualGraph(DM dm, PetscInt *numCells, std::vector<idx_t> *offsets, std::vector<idx_t> *adjacency);

// Partitions for DMPlexDistribute through PETSc's shell partitioner: METIS k-way of the dual graph (the mesh must be on
// rank 0) and recursive coordinate bisection of the cell centroids (any distribution, deterministic).
PetscErrorCode setMetisPartition(DM dm, PetscPartitioner part);
PetscErrorCode setRcbPartition(DM dm, PetscPartitioner part);

// -element: p2 sets mesh->quadratic (a gmsh tetrahedral mesh only: a one-line error otherwise) and numbers the edges
// of the serial mesh `loaded` (on rank 0) after its vertices in `natural`; numEdgesGlobal is their count. Collective.
PetscErrorCode chooseElement(MPI_Comm comm, DM loaded, bool hdf5, Mesh *mesh, std::vector<PetscInt> *natural,
                             PetscInt *numEdgesGlobal);
// The distributed tetrahedral mesh refined once into the quadratic mesh's DM (mesh/mesh.hpp: quadratic): its vertices
// are the P2 nodes with natural ids, its elements the cells as read. pointNatural: the natural id of every point of
// mesh->dm (cells, vertices and edges). Collective.
// Rank 0: the position of every edge's node of the serial mesh `loaded` from a second-order file's edge nodes (3
// numbers per point of the chart, NaN for points that are no edge); none (empty) for a linear file: the edge nodes then
// sit at the middles. A file whose edge nodes do not match the mesh's edges, or lie far from their edge's middle, is
// refused with a one-line error. Collective.
PetscErrorCode placeEdgeNodes(MPI_Comm comm, DM loaded, const Mesh &mesh, const std::vector<GmshFacets::EdgeNode> &nodes,
                              std::vector<double> *edgeX);
// The edge nodes' positions carried from the loaded mesh to the distributed one `dm` by the migration SF (none on one
// rank: a copy); empty stays empty. Collective.
PetscErrorCode migrateEdgeNodes(PetscSF migration, const std::vector<double> &loaded, DM dm, std::vector<double> *local);
// pointEdgeX (optional, 3 per point of mesh->dm): the edge nodes' positions (curved edges of a second-order file).
PetscErrorCode refineToQuadratic(Mesh *mesh, const std::vector<PetscInt> &pointNatural, PetscInt numEdgesGlobal,
                                 const std::vector<double> &pointEdgeX);

}  // namespace aries::fem::loading
