// 1. RigidMotionRemoval (newton_steps.hpp): the rigid-motion share of a floating body's direction at the state X:
// the six infinitesimal rigid motions of the current positions, orthonormalized (PETSc's rigid-body null space).
// The gradient is orthogonal to them (the energy is invariant under rigid motions), so the slope is unchanged.
#include "solver/newton.hpp"

namespace aries::solver {

PetscErrorCode RigidMotionRemoval::shapeDirection(NewtonContext &ctx, Direction &, Vec X, Vec Y, Vec, PetscBool *) {
  MatNullSpace nsp;
  PetscFunctionBeginUser;
  PetscCall(rigidBodyModes(X, ctx.disc->dofsPerVertex(), &nsp));
  PetscCall(MatNullSpaceRemove(nsp, Y));
  PetscCall(MatNullSpaceDestroy(&nsp));
  PetscFunctionReturn(0);
}

}  // namespace aries::solver
