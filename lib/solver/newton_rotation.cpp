// The rotational update of NewtonSolver (-newton_rotation, newton.hpp) and the removal of a floating body's
// rigid-motion share from a direction (setFloating, the detached start).
#include "solver/local_vec.hpp"
#include "solver/newton.hpp"

#include <cmath>
#include <utility>

namespace aries::solver {

// The rotational update (-newton_rotation): the candidate step for the direction scale * Y (x_new = X - cand), each
// vertex turned by its spin (fem::Discretization::rotationalStep), and the energy there.
PetscErrorCode NewtonSolver::rotationalCandidate(Vec X, Vec Y, double scale, Vec cand, PetscReal *energy) {
  const DM dm = disc_->dm();
  LocalVec xl(dm), dl(dm);
  Vec out;
  PetscFunctionBeginUser;
  PetscCall(xl.fromGlobal(X, disc_));
  PetscCall(VecScale(Y, -scale));  // the displacement is -Y
  PetscCall(dl.fromGlobal(Y, nullptr));
  PetscCall(VecScale(Y, -1.0 / scale));
  PetscCall(DMGetLocalVector(dm, &out));
  PetscCall(PetscLogStagePush(assemblyStage_));
  PetscCall(disc_->rotationalStep(xl.get(), dl.get(), out));
  PetscCall(PetscLogStagePop());
  PetscCall(DMLocalToGlobal(dm, out, INSERT_VALUES, cand));
  PetscCall(DMRestoreLocalVector(dm, &out));
  PetscCall(VecScale(cand, -1.0));
  PetscCall(VecWAXPY(work_, -1.0, cand, X));
  PetscCall(energyAt(work_, energy, nullptr));
  PetscFunctionReturn(0);
}

// Replaces the direction Y by its rotational form when that lowers the energy at full length more than Y does, then
// doubles the angle up to rotation_ times while the energy keeps falling. The line search then runs on the result.
PetscErrorCode NewtonSolver::rotate(Vec X, Vec Y, Vec F, PetscBool *changed) {
  PetscFunctionBeginUser;
  if (rotation_ < 0) PetscFunctionReturn(0);
  Vec cand, best;
  PetscReal ePlain, eBest;
  PetscCall(VecWAXPY(work_, -1.0, Y, X));
  PetscCall(energyAt(work_, &ePlain, nullptr));
  PetscCall(VecDuplicate(Y, &cand));
  PetscCall(VecDuplicate(Y, &best));
  PetscCall(rotationalCandidate(X, Y, 1.0, best, &eBest));
  double scale = 1.0;
  if (eBest < ePlain && eBest < energyBefore_) {
    for (PetscInt k = 1; k <= rotation_; ++k) {
      PetscReal e;
      PetscCall(rotationalCandidate(X, Y, 2.0 * scale, cand, &e));
      if (!(e < eBest)) break;
      eBest = e;
      scale *= 2.0;
      std::swap(cand, best);
    }
    PetscScalar slope;
    PetscCall(VecDot(F, best, &slope));
    if (slope > 0.0) {  // a descent direction for the line search (x = X - lambda Y)
      PetscCall(VecCopy(best, Y));
      slope_ = slope;
      pending_.rotation = scale;
      *changed = PETSC_TRUE;
    }
  }
  PetscCall(VecDestroy(&cand));
  PetscCall(VecDestroy(&best));
  PetscFunctionReturn(0);
}

// The rigid-motion share of a direction at the state X (setFloating): the six infinitesimal rigid motions of the
// current positions, orthonormalized (PETSc's rigid-body null space). The gradient is orthogonal to them (the
// energy is invariant under rigid motions), so the slope is unchanged.
PetscErrorCode NewtonSolver::removeRigidMotion(Vec X, Vec Y) {
  Vec coords;
  MatNullSpace nsp;
  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(X, &coords));
  PetscCall(VecSetBlockSize(coords, disc_->dofsPerVertex()));
  PetscCall(VecCopy(X, coords));
  PetscCall(MatNullSpaceCreateRigidBody(coords, &nsp));
  PetscCall(MatNullSpaceRemove(nsp, Y));
  PetscCall(MatNullSpaceDestroy(&nsp));
  PetscCall(VecDestroy(&coords));
  PetscFunctionReturn(0);
}

}  // namespace aries::solver
