// Solving a degenerate start's stretch terms before its volume terms (the shape stage), shared by the static
// detached start (detached_start.cpp: always, on the detached body) and by the first backward Euler step from a
// synthetic start that holds far more volume-term energy than other elastic energy (Simulation::advance,
// -beuler_shape_first X: a scrambled body, where a cell stretched by s holds volume energy ~ lambda s^6 against
// ~ mu s^2; not an inside-out start, J = -1 without stretch, where the ratio is of the order of lambda / mu).
//
// Why: a scrambled cell is stretched by about L / h, so J grows like the cube of the stretch and the volume term
// lambda/2 (J - J0)^2 like its sixth power, with a Hessian lambda cof F (x) cof F + lambda (J - J0) d2J whose
// curvatures outgrow the stretch terms' (mu |F - R|^2: the square) and the mass term by orders of magnitude. Newton
// on such a term shrinks the stretch by a fixed factor per update (s^6 loses 1/5 of s per Newton step), and its
// linear systems are so badly scaled that CG + Jacobi stalls at -ksp_max_it: at nu = 0.3 a dynamic scramble's first
// step took 97 updates and 430k CG iterations (33 solves at the limit) where nu = 0 (no volume term) took 18 and 795;
// with the stage, 31 and 5.9k (camel, 16.6k tets, seed 1, 2 ranks: bench/results/degenerate_starts.md).
// Without the volume terms the stretch terms gather the body in a few updates; the full energy then starts from a
// state whose cells are near their rest shapes, where the volume term is well scaled. The step's solution is the full
// energy's either way: the stage only moves the point Newton starts from. The stage's updates, linear solves and
// history are the step's.
//
// So the dynamic stage need not converge to -newton_tol: it stops at a Newton step of `stageTol` L
// (-beuler_shape_first_tol, default 0.1 L: on the scrambles measured, after its first update). Converged to
// -newton_tol it spent 10-15 more updates, about a whole nu = 0 step, on the stretch terms' linear tail, at a state
// the volume terms then move at once (camel, seed 3: the stage ended at |r| 0.06, the full solve began at 1.6e4).
// The static detached start keeps its full solve: there the loose stage was measured not to help (camel invert at
// nu 0.3: 66 updates against 52).
#include "solver/local_vec.hpp"
#include "solver/simulation.hpp"

namespace aries::solver {

// The volume terms' elastic energy at x over the other terms' (0 without volume terms), against minRatio.
PetscErrorCode volumeDominated(fem::Discretization &disc, Vec x, double minRatio, bool *dominated) {
  PetscReal full = 0.0, shape = 0.0;
  PetscFunctionBeginUser;
  *dominated = false;
  if (!disc.suspendVolumeTerms(true)) PetscFunctionReturn(0);  // no volume term (nu = 0): nothing evaluated
  LocalVec local(disc.dm());
  PetscErrorCode ierr = local.fromGlobal(x, &disc);
  if (!ierr) ierr = disc.diagnostics().elasticEnergy(local.get(), &shape);
  disc.suspendVolumeTerms(false);  // before any error returns: the materials are the read ones again
  PetscCall(ierr);
  PetscCall(disc.diagnostics().elasticEnergy(local.get(), &full));
  *dominated = (full - shape) / std::max(shape, 1e-300) > minRatio;
  PetscFunctionReturn(0);
}

PetscErrorCode solveShapeFirst(fem::Discretization &disc, NewtonSolver &newton, Vec x, double minRatio,
                               double stageTol, NewtonResult *acc) {
  bool fixes = false;
  PetscFunctionBeginUser;
  if (minRatio > 0.0) {
    bool dominated = false;
    PetscCall(volumeDominated(disc, x, minRatio, &dominated));
    if (!dominated) PetscFunctionReturn(0);
  }
  PetscCall(disc.stretchTermsFixShape(&fixes));
  if (!fixes || !disc.suspendVolumeTerms(true)) PetscFunctionReturn(0);
  Vec start;
  PetscCall(VecDuplicate(x, &start));
  PetscCall(VecCopy(x, start));
  NewtonResult stage;
  PetscErrorCode ierr = newton.loosenStepTolerance(stageTol * disc.mesh().diagonal);
  if (!ierr) ierr = newton.solve(x, &stage);
  if (!ierr) ierr = newton.loosenStepTolerance(0.0);  // the full solve converges to -newton_tol
  disc.suspendVolumeTerms(false);  // before any error returns: the materials are the read ones again
  newton.energyChanged();           // the full solve's first system is filtered (-newton_exact_start)
  PetscCall(ierr);
  *acc += stage;
  if (!stage.converged()) PetscCall(VecCopy(start, x));  // the full solve starts from the start it would have had
  PetscCall(VecDestroy(&start));
  PetscFunctionReturn(0);
}

}  // namespace aries::solver
