// Scoped local copy of a global vector, for the Newton solver's passes over the discretization.
#pragma once

#include "fem/discretization.hpp"

#include <petscdm.h>

#include <algorithm>
#include <vector>

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

// The key of a value remembered for one state: that state's local values (boundary values included). matches() says
// whether a local vector holds exactly them (bit for bit; NaN never matches) and, where it does not, takes its values
// as the new key. Per rank: a remembered sum over ranks must agree on the answer (MPI_MIN) before using it.
class LocalStateKey {
 public:
  PetscErrorCode matches(Vec local, bool *same) {
    const PetscScalar *x;
    PetscInt n;
    PetscFunctionBeginUser;
    PetscCall(VecGetLocalSize(local, &n));
    PetscCall(VecGetArrayRead(local, &x));
    *same = values_.size() == static_cast<size_t>(n) && std::equal(x, x + n, values_.begin());
    if (!*same) values_.assign(x, x + n);
    PetscCall(VecRestoreArrayRead(local, &x));
    PetscFunctionReturn(0);
  }

 private:
  std::vector<PetscScalar> values_;
};

}  // namespace aries::solver
