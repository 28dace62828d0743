// Structural check of a gmsh file before PETSc reads it, so a malformed file gets one message naming the file, the
// line and what is wrong instead of a reader traceback: regular file with the .msh extension, $MeshFormat 2.x or
// 4.x, for ASCII files the $Nodes/$Elements counts and line shapes, defined node references, and supported element
// types (tetrahedra with 4 or 10 nodes, triangles and trilinear hexahedra, lines, triangles, quadrangles and points for
// boundary groups). Binary files are checked only through their header.
#pragma once

#include <petscsys.h>

#include <array>
#include <string>
#include <vector>

namespace aries::fem {

// What the check learns about the node coordinates (ASCII files only; coordinatesKnown is false for binary files).
struct GmshFacts {
  bool coordinatesKnown = false;
  double zRange = 0.0;   // max z - min z over the nodes
  double extent = 0.0;   // largest side of the nodes' bounding box
};

// The faces of an ASCII gmsh file (MSH 2.2 or 4.1) that carry a physical tag, as PETSc 3.18's reader labels them under
// its default options ("Face Sets" for elements one dimension below the cells, the first physical tag as the value; it
// labels no lines in 3D), with their corners in PETSc's serial vertex numbering (the nodes in file order, counting
// those that are a corner of some element). A mesh read without its faces and edges can be labelled from them after it
// is distributed and interpolated in parallel (mesh/mesh.cpp). Read on rank 0 only.
struct GmshFacets {
  struct Facet {
    int dim = 0, tag = 0, numCorners = 0;
    std::array<long, 4> vertex{};     // serial vertex numbers of the corners
    std::array<double, 12> corner{};  // their coordinates, as the file gives them (to check the numbering against)
  };
  bool known = false;  // ASCII 2.2 or 4.1 without a $Periodic section: the lists below are complete
  int cellDim = 0;     // the largest element dimension (PETSc's cells)
  long numVertices = 0;
  std::vector<Facet> facets;
  // The edge nodes of 10-node tetrahedra (any ASCII file): one per edge, sorted by the corners' serial vertex numbers
  // (a < b). The quadratic elements (-element p2) take their edge nodes from here: curved where the file's are.
  struct EdgeNode {
    long a = 0, b = 0;
    std::array<double, 3> x{};
  };
  std::vector<EdgeNode> edgeNodes;
};

// Collective: rank 0 reads the file; every rank raises the same PETSC_ERR_USER_INPUT on a problem and receives the
// same facts. `option`: the option that named the file, for the error messages. `facets` (rank 0, optional): the
// tagged faces and edges, when the format allows.
PetscErrorCode validateGmshFile(MPI_Comm comm, const std::string &file, GmshFacts *facts,
                                const std::string &option = "-dm_plex_filename", GmshFacets *facets = nullptr);

}  // namespace aries::fem
