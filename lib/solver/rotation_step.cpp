// 4. RotationalUpdate (newton_steps.hpp, -newton_rotation). A Newton step is linear in the positions, so it can only
// turn a part of the body along the tangent of its rotation (stretching it); where the direction is locally a
// rotation (its spin, the skew part of grad_x of the step, averaged per vertex) the vertex follows the circle by the
// same angle instead, and up to K doublings of that angle are tried while the energy falls. Taken only where it
// lowers the energy more than the plain direction and stays a descent direction. Unwinding a body twisted about its
// supports (static solves from scrambled starts) otherwise takes dozens of short Newton steps.
#include "solver/local_vec.hpp"
#include "solver/newton_steps.hpp"

#include <utility>

namespace aries::solver {

// Replaces the direction Y by its rotational form (fem::Discretization::vertexSpin / turnBySpin; x_new = X - Y) when
// that lowers the energy at full length more than Y does, then doubles the angle up to K times while the energy
// keeps falling. The line search then runs on the result.
PetscErrorCode RotationalUpdate::shapeDirection(NewtonContext &ctx, Direction &d, Vec X, Vec Y, Vec F,
                                                PetscBool *changed) {
  PetscFunctionBeginUser;
  fem::Discretization *disc = ctx.disc;
  const fem::Kinematics &kin = disc->kinematics();
  const DM dm = disc->dm();
  LocalVec xl(dm), dl(dm);
  std::vector<double> spin;
  PetscCall(xl.fromGlobal(X, disc));
  PetscCall(VecScale(Y, -1.0));  // the displacement is -Y
  PetscCall(dl.fromGlobal(Y, nullptr));
  PetscCall(VecScale(Y, -1.0));
  PetscCall(ctx.beginAssembly());
  PetscCall(kin.vertexSpin(xl.get(), dl.get(), &spin));
  PetscCall(ctx.endAssembly());
  Vec out, cand, best;
  PetscCall(DMGetLocalVector(dm, &out));
  PetscCall(VecDuplicate(Y, &cand));
  PetscCall(VecDuplicate(Y, &best));
  // The direction Y' = -(turned scale * displacement) and the energy at X - Y'.
  const auto candidate = [&](double scale, Vec dir, PetscReal *energy) -> PetscErrorCode {
    PetscFunctionBeginUser;
    PetscCall(kin.turnBySpin(spin, dl.get(), scale, out));
    PetscCall(DMLocalToGlobal(dm, out, INSERT_VALUES, dir));
    PetscCall(VecScale(dir, -1.0));
    PetscCall(VecWAXPY(ctx.work, -1.0, dir, X));
    PetscCall(ctx.energyAt(ctx.work, energy, nullptr));
    PetscFunctionReturn(0);
  };
  PetscReal ePlain, eBest;
  PetscCall(VecWAXPY(ctx.work, -1.0, Y, X));
  PetscCall(ctx.energyAt(ctx.work, &ePlain, nullptr));
  PetscCall(candidate(1.0, best, &eBest));
  double scale = 1.0;
  if (eBest < ePlain && eBest < d.energyBefore) {
    for (PetscInt k = 1; k <= opts_.doublings; ++k) {
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
      d.slope = slope;
      d.record.rotation = scale;
      *changed = PETSC_TRUE;
    }
  }
  PetscCall(DMRestoreLocalVector(dm, &out));
  PetscCall(VecDestroy(&cand));
  PetscCall(VecDestroy(&best));
  PetscFunctionReturn(0);
}

}  // namespace aries::solver
