// Per-cell input files (fibers, ...). Format (docs/options.md):
//   # comment lines anywhere
//   N                      number of cells (must equal the mesh's top-dimensional gmsh elements)
//   v1 v2 [v3]             one line per cell in gmsh element order; C numbers (or 3 with z = 0 for 2D elements)
// Vectors are normalized; zero-length or non-finite vectors are errors naming the file and line.
#pragma once

#include <petscsys.h>

#include <string>
#include <vector>

namespace aries::fem {

// Reads on rank 0, validates, broadcasts `numCells * comps` values (unit vectors) to every rank. Collective.
PetscErrorCode readCellVectorFile(MPI_Comm comm, const std::string &file, const char *option, PetscInt numCells,
                                  int comps, std::vector<double> *values);

}  // namespace aries::fem
