// The load increment inside the Newton solve (newton.hpp, -lift_increments): how every finite-element code applies a
// prescribed motion, kept inversion-safe.
//
// A step moves the load parameter from s (the state's) to its target t: the supports go from g(s) to g(t), the surface
// loads and keyframed fields to their values at t. Moving only the supports leaves the interior behind and crushes the
// layer next to a moved support; the increment then had to be halved until the alpha safeguard accepted it, a Newton
// solve per half, and the halvings grew with the mesh. Here the first linear solves carry the increment: with the
// model at t and the supports still at g(s) (state x), d = g(t) - g(s) at the prescribed dofs,
//
//     H_ff p = r_f + H_fd d        (r the gradient, H the filtered Hessian at that state; the update is x - p),
//
// the Newton step of the problem at t whose prescribed dofs move by d ("lifting": DOLFINx's apply_lifting, deal.II's
// inhomogeneous constraints in the first iteration, FEBio's prescribed-displacement increments). The combined update
// (interior -p, supports +d) is one update of the solve:
//   * convergence: a converged linear solve whose combined step is at most the tolerance in the inf-norm (both -p and
//     d) is the solve's final correction, as in the plain Newton iteration (ConvergenceCheck);
//   * the alpha safeguard and a merit test shorten the combined update as one: at length lambda the supports and the
//     rest of the model are at load s + lambda (t - s) and the interior at x - lambda p. A length is accepted when no
//     guarded cell ends below -alpha_min (AlphaSafeguard::acceptable against the alphas at (x, g(s))) and the interior's
//     move lowers the total potential at that load against leaving the interior where it is (the quadratic model says
//     it does at lambda = 1 by p^T H p / 2 whatever x is; a far-off linearization, e.g. of a large rotation, may not);
//   * a shortened update leaves the rest of the increment for the next lifted solve, from the state it reached (the
//     load then is between s and t): each lifted solve both moves the supports and corrects the equilibrium;
//   * when the target is reached, plain Newton (the SNES iteration) continues at fixed supports.
// Only where no length down to 2^-kMaxLiftHalvings can be accepted does the solve hand the increment back unchanged
// (advanced = false): the time stepper then falls back to moving the supports alone in halved load sub-steps
// (simulation.cpp), the old path.
#include "solver/local_vec.hpp"
#include "solver/newton.hpp"

#include <cmath>

namespace aries::solver {

namespace {
// Lengths of a lifted update tried: 1, 1/2, ..., 2^-kMaxLiftHalvings (the time stepper's -load halvings had 20).
constexpr int kMaxLiftHalvings = 20;
// Lifted updates in one solve before plain Newton takes over at the load reached (the rest: a load sub-step).
constexpr int kMaxLiftedUpdates = 30;
}  // namespace

PetscErrorCode NewtonSolver::setLoad(double load) {
  PetscFunctionBeginUser;
  fem::StepState step = ctx_.disc->step();
  if (step.load == load) PetscFunctionReturn(0);
  step.load = load;
  ctx_.energyMemo.valid = false;  // the potential of every state changes with the load
  PetscCall(ctx_.disc->setStep(step));
  PetscFunctionReturn(0);
}

// The gradient of the total potential at a local state, as a global vector (free dofs).
PetscErrorCode NewtonSolver::gradientAt(Vec xLocal, Vec gLocal, Vec gGlobal) {
  PetscFunctionBeginUser;
  PetscCall(ctx_.beginAssembly());
  PetscCall(ctx_.disc->gradient(xLocal, gLocal));
  PetscCall(ctx_.endAssembly());
  PetscCall(VecSet(gGlobal, 0.0));
  PetscCall(DMLocalToGlobal(ctx_.disc->dm(), gLocal, ADD_VALUES, gGlobal));
  PetscFunctionReturn(0);
}

// The lifted direction at the model of load `target` with the supports at g(s): b = r_f + H_fd d (the coupling H_fd d
// given), H_ff p = b with the Newton solver's KSP (a new preconditioner unless -multigrid_reuse_growth keeps the last
// one, a zero start, at -ksp_rtol; PETSc's Eisenstat-Walker hook, which only works inside SNESSolve, off for it).
// rec: the row's energy, residual, step and Krylov iterations.
PetscErrorCode NewtonSolver::liftedDirection(Vec xLocal, Vec coupling, Vec b, Vec p, IterationRecord *rec,
                                             bool *solved) {
  NewtonContext &c = ctx_;
  fem::Discretization &disc = *c.disc;
  LocalVec gl(disc.dm());
  PetscFunctionBeginUser;
  PetscReal magnitude;
  PetscCall(c.beginAssembly());
  PetscCall(disc.objective(xLocal, &rec->energy, &magnitude));
  PetscCall(c.endAssembly());
  PetscCall(gl.zeros());
  PetscCall(gradientAt(xLocal, gl.get(), b));
  PetscCall(VecNorm(b, NORM_2, &rec->residual));
  PetscCall(VecAXPY(b, 1.0, coupling));
  PetscCall(c.beginAssembly());
  PetscCall(disc.hessian(xLocal, c.J));
  PetscCall(c.endAssembly());
  KSP ksp;
  PetscBool guess, ew;
  PetscReal rtol, abstol, dtol;
  PetscInt maxit, its;
  KSPConvergedReason reason;
  PetscCall(SNESGetKSP(c.snes, &ksp));
  PetscCall(KSPGetInitialGuessNonzero(ksp, &guess));
  PetscCall(KSPGetTolerances(ksp, &rtol, &abstol, &dtol, &maxit));
  PetscCall(SNESKSPGetUseEW(c.snes, &ew));
  PetscCall(SNESKSPSetUseEW(c.snes, PETSC_FALSE));
  PetscCall(KSPSetTolerances(ksp, check_->baseLinearRtol(), abstol, dtol, maxit));
  PetscCall(KSPSetInitialGuessNonzero(ksp, PETSC_FALSE));
  PetscCall(KSPSetReusePreconditioner(ksp, c.preconditioner.beginSystem() ? PETSC_FALSE : PETSC_TRUE));
  PetscCall(KSPSetOperators(ksp, c.J, c.J));
  PetscCall(KSPSolve(ksp, b, p));
  PetscCall(KSPGetConvergedReason(ksp, &reason));
  c.countLinearSolve(reason);
  PetscCall(c.finishSystem(ksp, b, p));  // may solve it again with a new preconditioner
  PetscCall(KSPSetTolerances(ksp, rtol, abstol, dtol, maxit));
  PetscCall(KSPSetInitialGuessNonzero(ksp, guess));
  PetscCall(SNESKSPSetUseEW(c.snes, ew));
  PetscCall(KSPGetConvergedReason(ksp, &reason));
  PetscCall(KSPGetIterationNumber(ksp, &its));
  rec->linearIterations = its;
  rec->preconditionerBuilt = c.preconditioner.built();
  PetscCall(VecNorm(p, NORM_INFINITY, &rec->stepInf));
  *solved = linearSolveSolved(reason);
  PetscFunctionReturn(0);
}

// The longest acceptable length 2^-k of the combined update (see the top of this file): the load s + lambda (t - s)
// (t itself at lambda = 1), the interior x - lambda p. A certifying update is judged by the safeguard alone at full
// length (its energy change is round-off). *lambda = 0: none.
PetscErrorCode NewtonSolver::liftedLength(Vec x, Vec p, double s, double target, const std::vector<double> &alphaRef,
                                          bool certifying, double *lambda) {
  NewtonContext &c = ctx_;
  Vec w = lift_.trial;
  PetscFunctionBeginUser;
  double length = 1.0;
  *lambda = 0.0;
  for (int k = 0; k <= kMaxLiftHalvings; ++k, length *= 0.5) {
    PetscCall(setLoad(k == 0 ? target : s + length * (target - s)));
    PetscCall(VecWAXPY(w, -length, p, x));
    bool ok = false;
    PetscCall(safeguard_->acceptable(c, w, alphaRef, &ok));
    if (!ok) {
      ++c.result.safeguardHalvings;
      continue;
    }
    if (certifying && k == 0) {
      *lambda = 1.0;
      break;
    }
    PetscReal moved, left, magnitude;
    PetscCall(c.energyAt(w, &moved, &magnitude));
    PetscCall(c.energyAt(x, &left, nullptr));
    const double roundoff = kRoundoffSafety * kernels::kEps * magnitude;
    if (std::isfinite(moved) && (!std::isfinite(left) || moved <= left + roundoff)) {
      *lambda = length;
      break;
    }
  }
  PetscFunctionReturn(0);
}

// -lift_increments auto with inertia: the supports moved alone, where the safeguard accepts that move, start a step
// that costs no more than the lifted one and usually less (measured on Table 1's Fig. 3/6 rows, bench/newton_work.py:
// at nu = 0.49 lifting every step took 1.99 Newton updates per step against 0.70 and 0.26). Inertia holds the interior
// over a time step, so the interior's response to the supports' increment is small and the first Newton direction
// from the moved supports often certifies convergence at once, where a lifted update (the supports' increment is part
// of its step) never does.
bool NewtonSolver::supportsAloneFirst() const {
  return opts_.lift == LiftMode::Auto && ctx_.dynamic;
}

// One lifted update from the discretization's load s towards `target` (see the top of this file). *advanced: the state
// and the load moved; *converged: the combined step was the final correction (the load is the target). A load step
// that moves no prescribed value (pinned supports, only surface loads or fields changing) has nothing to lift: it is
// handed back at once, and the time stepper moves the load before a plain Newton solve. (A backward Euler step under
// auto whose supports may move alone, supportsAloneFirst, does not come here: Simulation::solveToLoad.)
PetscErrorCode NewtonSolver::liftedUpdate(Vec x, double target, bool *advanced, bool *converged) {
  NewtonContext &c = ctx_;
  fem::Discretization &disc = *c.disc;
  const DM dm = disc.dm();
  const double s = disc.load();
  PetscFunctionBeginUser;
  *advanced = false;
  *converged = false;
  if (!lift_.rhs) {
    PetscCall(VecDuplicate(c.work, &lift_.rhs));
    PetscCall(VecDuplicate(c.work, &lift_.step));
    PetscCall(VecDuplicate(c.work, &lift_.trial));
    PetscCall(VecDuplicate(c.work, &lift_.coupling));
  }
  // The supports' increment d = g(t) - g(s) (zero at the free dofs) and the state with the supports at g(s).
  LocalVec xl(dm), dl(dm), from(dm);
  PetscCall(dl.zeros());
  PetscCall(from.zeros());
  PetscCall(disc.fillBoundary(dl.get(), target));
  PetscCall(disc.fillBoundary(from.get(), s));
  PetscCall(VecAXPY(dl.get(), -1.0, from.get()));
  PetscReal incrementInf, local;
  PetscCall(VecNorm(dl.get(), NORM_INFINITY, &local));  // a local vector: every rank's share, then the max
  PetscCallMPI(MPI_Allreduce(&local, &incrementInf, 1, MPI_DOUBLE, MPI_MAX, PetscObjectComm((PetscObject)x)));
  if (incrementInf == 0.0) PetscFunctionReturn(0);
  PetscCall(setLoad(target));  // the surface loads and fields at the target
  PetscCall(xl.fromGlobal(x, &disc));
  PetscCall(VecAXPY(xl.get(), -1.0, dl.get()));
  std::vector<double> alphaRef, bandTop;
  disc.mollifierBandTop(&bandTop);
  PetscCall(disc.cellGuard(xl.get(), safeguard_->exactBelow(bandTop), &alphaRef));
  {  // the coupling H_fd d, a global vector (only the cells next to the supports are evaluated)
    LocalVec hd(dm);
    PetscCall(hd.zeros());
    PetscCall(c.beginAssembly());
    PetscCall(disc.hessianProduct(xl.get(), dl.get(), hd.get()));
    PetscCall(c.endAssembly());
    PetscCall(VecSet(lift_.coupling, 0.0));
    PetscCall(DMLocalToGlobal(dm, hd.get(), ADD_VALUES, lift_.coupling));
  }

  IterationRecord rec;
  rec.iteration = c.iterationOffset;
  rec.lifted = true;
  rec.filter = filterTag(disc.eigenFilter());
  bool solved = false;
  PetscCall(liftedDirection(xl.get(), lift_.coupling, lift_.rhs, lift_.step, &rec, &solved));
  rec.stepInf = std::max<double>(rec.stepInf, incrementInf);  // the combined step: interior and supports
  const bool certifying = solved && rec.stepInf <= c.stepTol;
  double lambda = 0.0;
  PetscCall(liftedLength(x, lift_.step, s, target, alphaRef, certifying, &lambda));
  rec.lambda = lambda;
  if (lambda == 0.0) {  // the increment is handed back: the state and the load as they were
    PetscCall(setLoad(s));
    rec.load = s;
    c.result.history.push_back(rec);
    PetscFunctionReturn(0);
  }
  PetscCall(VecCopy(lift_.trial, x));
  rec.load = disc.load();
  c.result.history.push_back(rec);
  *advanced = true;
  Direction lifted;
  lifted.halved = lambda < 1.0;
  PetscCall(filter_->finishUpdate(c, lifted, x, lambda));  // the next system's filter, as after any update
  if (certifying && lambda == 1.0) {
    *converged = true;
    c.result.convergence = c.iterationOffset == 0 ? Convergence::Initial : Convergence::NewtonStep;
    c.result.reason = SNES_CONVERGED_SNORM_RELATIVE;
  } else {
    ++c.iterationOffset;  // an update of the state
  }
  PetscFunctionReturn(0);
}

// Lifted updates until the load reaches `target`, the combined step converges, no length is acceptable or
// kMaxLiftedUpdates were taken.
PetscErrorCode NewtonSolver::liftIncrement(Vec x, double target, bool *advanced, bool *converged) {
  PetscFunctionBeginUser;
  *advanced = false;
  *converged = false;
  for (int k = 0; k < kMaxLiftedUpdates && ctx_.disc->load() != target && !*converged; ++k) {
    bool moved = false;
    PetscCall(liftedUpdate(x, target, &moved, converged));
    if (!moved) break;
    *advanced = true;
  }
  PetscFunctionReturn(0);
}

}  // namespace aries::solver
