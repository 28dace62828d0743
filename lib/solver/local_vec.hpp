// Scoped local copy of a global vector, for the Newton solver's passes over the discretization.
#pragma once

#include "fem/discretization.hpp"

#include <petscdm.h>

namespace aries::solver {

// Zeros at the Dirichlet dofs unless the boundary is filled (fromGlobal with the discretization).
class LocalVec {
 public:
  explicit LocalVec(DM dm) : dm_(dm) {}
  LocalVec(const LocalVec &) = delete;
  LocalVec &operator=(const LocalVec &) = delete;
  ~LocalVec() {
    if (v_) DMRestoreLocalVector(dm_, &v_);
  }
  PetscErrorCode fromGlobal(Vec g, const fem::Discretization *fillBoundaryOf) {
    PetscFunctionBeginUser;
    PetscCall(DMGetLocalVector(dm_, &v_));
    PetscCall(VecSet(v_, 0.0));
    PetscCall(DMGlobalToLocal(dm_, g, INSERT_VALUES, v_));
    if (fillBoundaryOf) PetscCall(fillBoundaryOf->fillBoundary(v_));
    PetscFunctionReturn(0);
  }
  PetscErrorCode zeros() {
    PetscFunctionBeginUser;
    PetscCall(DMGetLocalVector(dm_, &v_));
    PetscCall(VecSet(v_, 0.0));
    PetscFunctionReturn(0);
  }
  Vec get() const { return v_; }

 private:
  DM dm_;
  Vec v_ = nullptr;
};

}  // namespace aries::solver
