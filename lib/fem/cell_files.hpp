// Per-cell input files (fibers, ...). Format (docs/options.md):
//   # comment lines anywhere
//   N                      number of cells (must equal the mesh's top-dimensional gmsh elements)
//   v1 v2 [v3]             one line per cell in gmsh element order; C numbers (or 3 with z = 0 for 2D elements)
// Vectors are normalized; zero-length or non-finite vectors are errors naming the file and line.
//
// Shape-target keyframes (-target_file):
//   # comment lines anywhere
//   cells N keyframes K
//   time t_1               then N lines of the symmetric target S_t of each cell (gmsh element order):
//   s11 s22 s33 s12 s23 s13    (tets; planar elements: s11 s22 s12)
//   time t_2               ... K blocks, times strictly increasing
#pragma once

#include <petscsys.h>

#include <string>
#include <vector>

namespace aries::fem {

// Reads on rank 0, validates, broadcasts `numCells * comps` values (unit vectors) to every rank. Collective.
PetscErrorCode readCellVectorFile(MPI_Comm comm, const std::string &file, const char *option, PetscInt numCells,
                                  int comps, std::vector<double> *values);

// Reads a keyframe file on rank 0, validates it, broadcasts it: `times` (K) and `targets` (K x numCells x comps,
// comps = 6 for 3x3, 3 for 2x2 targets, in the order of the file). Collective.
PetscErrorCode readTargetKeyframeFile(MPI_Comm comm, const std::string &file, PetscInt numCells, int comps,
                                      std::vector<double> *times, std::vector<double> *targets);

}  // namespace aries::fem
