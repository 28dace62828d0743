// Where each local vertex's unknowns live: its offsets in the local and global vectors, whether this rank owns it,
// its Dirichlet set and its rest position. Built once by the discretization's DOF layout (dof_layout.cpp) and read by
// every energy term.
#pragma once

#include <petscsys.h>

#include <Eigen/Core>

#include <array>
#include <vector>

namespace aries::fem {

struct VertexInfo {
  PetscInt loc;     // offset of the first dof in the local vector
  PetscInt global;  // offset of its first free dof in the global vector (-1 if none); for owned only meaningful
  bool owned;
  int bcSet;        // the first Dirichlet set (BoundarySpec::sets, then the boxes) holding any component, -1 if none
  std::array<int, 3> fixedBy{-1, -1, -1};  // per component: the set prescribing it, -1 if free
  int numFree;      // free components: the vertex's dofs in the global vector, consecutive from `global`
  Eigen::Vector3d rest;
  bool fixed(int i) const { return fixedBy[i] >= 0; }
  // The global row of component i, -1 if it is prescribed (PETSc's Mat/VecSetValues skip negative indices).
  PetscInt row(int i) const {
    if (fixedBy[i] >= 0) return -1;
    PetscInt k = 0;
    for (int j = 0; j < i; ++j) k += fixedBy[j] < 0;
    return global + k;
  }
  bool offRankFree() const { return !owned && numFree > 0; }  // its Hessian rows go through another rank's stash
  bool ownedFree() const { return owned && numFree > 0; }     // owned, with at least one free component
};

using VertexTable = std::vector<VertexInfo>;

}  // namespace aries::fem
