// Where each local vertex's unknowns live: its offsets in the local and global vectors, whether this rank owns it,
// its Dirichlet set and its rest position. Built once by the discretization's DOF layout (dof_layout.cpp) and read by
// every energy term.
#pragma once

#include <petscsys.h>

#include <Eigen/Core>

#include <vector>

namespace aries::fem {

struct VertexInfo {
  PetscInt loc;     // offset of the first dof in the local vector
  PetscInt global;  // offset of the first dof in the global vector (-1 if Dirichlet); for owned only meaningful
  bool owned;
  int bcSet;        // index into BoundarySpec::sets (then the boxes), -1 if free
  Eigen::Vector3d rest;
  bool offRankFree() const { return !owned && bcSet < 0; }  // its Hessian rows go through another rank's stash
  bool ownedFree() const { return owned && bcSet < 0; }
};

using VertexTable = std::vector<VertexInfo>;

}  // namespace aries::fem
