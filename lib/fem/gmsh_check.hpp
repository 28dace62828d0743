// Structural check of a gmsh file before PETSc reads it, so a malformed file gets one message naming the file, the
// line and what is wrong instead of a reader traceback: regular file with the .msh extension, $MeshFormat 2.x or
// 4.x, for ASCII files the $Nodes/$Elements counts and line shapes, defined node references, and supported element
// types (linear tetrahedra, triangles and trilinear hexahedra, lines, quadrangles and points for boundary groups).
// Binary files are checked only through their header.
#pragma once

#include <petscsys.h>

#include <string>

namespace aries::fem {

// What the check learns about the node coordinates (ASCII files only; coordinatesKnown is false for binary files).
struct GmshFacts {
  bool coordinatesKnown = false;
  double zRange = 0.0;   // max z - min z over the nodes
  double extent = 0.0;   // largest side of the nodes' bounding box
};

// Collective: rank 0 reads the file; every rank raises the same PETSC_ERR_USER_INPUT on a problem and receives the
// same facts. `option`: the option that named the file, for the error messages.
PetscErrorCode validateGmshFile(MPI_Comm comm, const std::string &file, GmshFacts *facts,
                                const std::string &option = "-dm_plex_filename");

}  // namespace aries::fem
