// The rotational update of NewtonSolver (-newton_rotation, newton.hpp) and the removal of a floating body's
// rigid-motion share from a direction (setFloating, the detached start).
#include "solver/local_vec.hpp"
#include "solver/newton.hpp"

#include <cmath>
#include <utility>

namespace aries::solver {

// Replaces the direction Y by its rotational form (fem::Discretization::vertexSpin / turnBySpin; x_new = X - Y) when
// that lowers the energy at full length more than Y does, then doubles the angle up to rotation_ times while the
// energy keeps falling. The line search then runs on the result.
PetscErrorCode NewtonSolver::rotate(Vec X, Vec Y, Vec F, PetscBool *changed) {
  PetscFunctionBeginUser;
  if (rotation_ < 0) PetscFunctionReturn(0);
  const DM dm = disc_->dm();
  LocalVec xl(dm), dl(dm);
  std::vector<double> spin;
  PetscCall(xl.fromGlobal(X, disc_));
  PetscCall(VecScale(Y, -1.0));  // the displacement is -Y
  PetscCall(dl.fromGlobal(Y, nullptr));
  PetscCall(VecScale(Y, -1.0));
  PetscCall(PetscLogStagePush(assemblyStage_));
  PetscCall(disc_->vertexSpin(xl.get(), dl.get(), &spin));
  PetscCall(PetscLogStagePop());
  Vec out, cand, best;
  PetscCall(DMGetLocalVector(dm, &out));
  PetscCall(VecDuplicate(Y, &cand));
  PetscCall(VecDuplicate(Y, &best));
  // The direction Y' = -(turned scale * displacement) and the energy at X - Y'.
  const auto candidate = [&](double scale, Vec dir, PetscReal *energy) -> PetscErrorCode {
    PetscFunctionBeginUser;
    PetscCall(disc_->turnBySpin(spin, dl.get(), scale, out));
    PetscCall(DMLocalToGlobal(dm, out, INSERT_VALUES, dir));
    PetscCall(VecScale(dir, -1.0));
    PetscCall(VecWAXPY(work_, -1.0, dir, X));
    PetscCall(energyAt(work_, energy, nullptr));
    PetscFunctionReturn(0);
  };
  PetscReal ePlain, eBest;
  PetscCall(VecWAXPY(work_, -1.0, Y, X));
  PetscCall(energyAt(work_, &ePlain, nullptr));
  PetscCall(candidate(1.0, best, &eBest));
  double scale = 1.0;
  if (eBest < ePlain && eBest < energyBefore_) {
    for (PetscInt k = 1; k <= rotation_; ++k) {
      PetscReal e;
      PetscCall(candidate(2.0 * scale, cand, &e));
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
  PetscCall(DMRestoreLocalVector(dm, &out));
  PetscCall(VecDestroy(&cand));
  PetscCall(VecDestroy(&best));
  PetscFunctionReturn(0);
}

// The rigid-motion share of a direction at the state X (setFloating): the six infinitesimal rigid motions of the
// current positions, orthonormalized (PETSc's rigid-body null space). The gradient is orthogonal to them (the
// energy is invariant under rigid motions), so the slope is unchanged.
PetscErrorCode NewtonSolver::removeRigidMotion(Vec X, Vec Y) {
  MatNullSpace nsp;
  PetscFunctionBeginUser;
  PetscCall(rigidBodyModes(X, disc_->dofsPerVertex(), &nsp));
  PetscCall(MatNullSpaceRemove(nsp, Y));
  PetscCall(MatNullSpaceDestroy(&nsp));
  PetscFunctionReturn(0);
}

}  // namespace aries::solver
