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

// Every rank reads and validates the whole file (the same first error everywhere) but keeps only the lines of its
// block of the natural cell numbering; `values` then receives `comps` values (unit vectors) for each natural cell id of
// `cells` (this rank's local cells) from the ranks holding them. No rank holds a whole-mesh array. Collective.
PetscErrorCode readCellVectorFile(MPI_Comm comm, const std::string &file, const char *option, PetscInt numCells,
                                  const std::vector<PetscInt> &cells, int comps, std::vector<double> *values);

// A keyframe file, read the same way: `times` (K) and `targets` (K x cells.size() x comps: keyframe k of local cell c
// at (k * cells.size() + c) * comps; comps = 6 for 3x3, 3 for 2x2 targets, in the order of the file). Collective.
PetscErrorCode readTargetKeyframeFile(MPI_Comm comm, const std::string &file, PetscInt numCells,
                                      const std::vector<PetscInt> &cells, int comps, std::vector<double> *times,
                                      std::vector<double> *targets);

}  // namespace aries::fem
