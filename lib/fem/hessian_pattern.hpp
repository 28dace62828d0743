// The Hessian's nonzero pattern, recorded from the terms' own insertions and turned into the matrix's preallocation.
//
// Discretization::preallocateHessian lets every term add its Hessian once into a recorder with the matrix's sizes and
// block size, so every coupling a term makes is preallocated (an entry a term added elsewhere later would stop the
// assembly with PETSc's new-nonzero error); the elastic cells add zero matrices there (HessianAssembly::patternOnly).
// PETSc's MATPREALLOCATOR, used before, probes a hash set for every scalar entry (144 per tetrahedron) and has a quirk:
// a skipped column (-1, a held dof) is keyed as block -1 / bs, which C rounds to block 0, so every row next to a
// support got a zero block in block column 0 (0.3% of the entries on the peer box, 125k tets; GAMG's results move at
// round-off without them). The recorder is a MATSHELL whose MatSetValues / MatSetValuesBlocked append each (block row,
// block column) pair once per call (16 per tetrahedron) to its row's list; rows another rank owns go to it in one
// exchange; each list is sorted once. Then what MatPreallocatorPreallocate(P, PETSC_TRUE, J) does, call for call:
// MatXAIJSetPreallocation with the diagonal / off-diagonal (and upper-triangle) counts per block row,
// MAT_NEW_NONZERO_ALLOCATION_ERR, the pattern filled with zeros by one MatSetValuesBlocked per block row.
// ctest fem.element_scatter compares the two patterns. The peer box at 125k tets, 2 ranks: 0.46-0.56 s -> 0.13 s.
#pragma once

#include <petscmat.h>

#include <vector>

namespace aries::fem {

class HessianPattern {
 public:
  HessianPattern() = default;
  HessianPattern(const HessianPattern &) = delete;
  HessianPattern &operator=(const HessianPattern &) = delete;
  ~HessianPattern();
  // The recorder (a MATSHELL) with J's communicator, sizes and block size: give it to the terms' addHessian.
  PetscErrorCode create(Mat J);
  Mat recorder() const { return shell_; }
  // Collective: the recorded pattern becomes J's preallocation, filled with zeros and assembled; the recorder is gone.
  PetscErrorCode preallocate(Mat J);

 private:
  static PetscErrorCode setValues(Mat A, PetscInt m, const PetscInt rows[], PetscInt n, const PetscInt cols[],
                                  const PetscScalar values[], InsertMode mode);
  static PetscErrorCode setValuesBlocked(Mat A, PetscInt m, const PetscInt rows[], PetscInt n, const PetscInt cols[],
                                         const PetscScalar values[], InsertMode mode);
  // Appends block row br's columns cols[k] / unit (k < n, negative ones skipped, consecutive repeats once).
  void record(PetscInt br, PetscInt n, const PetscInt cols[], PetscInt unit);
  PetscErrorCode exchange(Mat J);  // the pairs of rows another rank owns, to their owners

  Mat shell_ = nullptr;
  PetscInt bs_ = 1;
  PetscInt rowStart_ = 0, rowEnd_ = 0;       // owned block rows
  std::vector<std::vector<PetscInt>> rows_;  // per owned block row: its block columns (sorted once at the end)
  std::vector<PetscInt> offRank_;            // (global block row, block column) pairs of rows others own
  bool noOffRank_ = true;                    // no rank recorded another rank's rows
};

}  // namespace aries::fem
