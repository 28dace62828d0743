#include "solver/newton.hpp"

#include "fem/options.hpp"

#include <cmath>
#include <string>

namespace aries::solver {

NewtonSolver::~NewtonSolver() {
  if (snes_) SNESDestroy(&snes_);
  if (J_) MatDestroy(&J_);
  if (work_) VecDestroy(&work_);
}

PetscErrorCode NewtonSolver::boundaryLocal(DM, Vec xLocal, void *ctx) {
  PetscFunctionBeginUser;
  PetscCall(static_cast<NewtonSolver *>(ctx)->disc_->fillBoundary(xLocal));
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonSolver::functionLocal(DM, Vec xLocal, Vec gLocal, void *ctx) {
  auto *self = static_cast<NewtonSolver *>(ctx);
  PetscFunctionBeginUser;
  PetscCall(PetscLogStagePush(self->assemblyStage_));
  PetscCall(self->disc_->gradient(xLocal, gLocal));
  PetscCall(PetscLogStagePop());
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonSolver::jacobianLocal(DM, Vec xLocal, Mat, Mat P, void *ctx) {
  auto *self = static_cast<NewtonSolver *>(ctx);
  PetscFunctionBeginUser;
  PetscCall(PetscLogStagePush(self->assemblyStage_));
  PetscCall(self->disc_->hessian(xLocal, P));
  PetscCall(PetscLogStagePop());
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonSolver::objectiveCallback(SNES, Vec x, PetscReal *value, void *ctx) {
  auto *self = static_cast<NewtonSolver *>(ctx);
  DM dm = self->disc_->dm();
  Vec xLocal;
  PetscFunctionBeginUser;
  PetscCall(PetscLogStagePush(self->assemblyStage_));
  PetscCall(DMGetLocalVector(dm, &xLocal));
  PetscCall(DMGlobalToLocal(dm, x, INSERT_VALUES, xLocal));
  PetscCall(self->disc_->fillBoundary(xLocal));
  PetscCall(self->disc_->objective(xLocal, value));
  PetscCall(DMRestoreLocalVector(dm, &xLocal));
  PetscCall(PetscLogStagePop());
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonSolver::alphasAt(Vec xGlobal, std::vector<double> *alpha) {
  DM dm = disc_->dm();
  Vec xLocal;
  PetscFunctionBeginUser;
  PetscCall(DMGetLocalVector(dm, &xLocal));
  PetscCall(DMGlobalToLocal(dm, xGlobal, INSERT_VALUES, xLocal));
  PetscCall(disc_->fillBoundary(xLocal));
  PetscCall(disc_->cellGuard(xLocal, alpha));
  PetscCall(DMRestoreLocalVector(dm, &xLocal));
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonSolver::alphaAcceptable(Vec xGlobal, const std::vector<double> &reference, bool *ok) {
  std::vector<double> alpha;
  MPI_Comm comm;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)xGlobal, &comm));
  PetscCall(alphasAt(xGlobal, &alpha));
  // Paper Sec. 4.2: a step must not *cause* alpha to become less than the threshold. Elements already below it
  // (an inside-out start has alpha = 0 everywhere) are left to the energy and its line search.
  int bad = 0;
  for (size_t c = 0; c < alpha.size() && !bad; ++c)
    bad = std::isnan(alpha[c]) || (reference[c] >= alphaMin_ && !(alpha[c] >= alphaMin_));
  int anyBad = 0;
  PetscCallMPI(MPI_Allreduce(&bad, &anyBad, 1, MPI_INT, MPI_MAX, comm));
  *ok = !anyBad;
  PetscFunctionReturn(0);
}

// Halve the Newton direction until the full step keeps every element's alpha acceptable (paper Sec. 4.2).
PetscErrorCode NewtonSolver::preCheck(SNESLineSearch, Vec X, Vec Y, PetscBool *changed, void *ctx) {
  auto *self = static_cast<NewtonSolver *>(ctx);
  PetscFunctionBeginUser;
  *changed = PETSC_FALSE;
  PetscCall(VecNorm(Y, NORM_INFINITY, &self->lastStepInf_));
  PetscCall(self->alphasAt(X, &self->alphaRef_));
  for (int k = 0; k < 60; ++k) {
    PetscCall(VecWAXPY(self->work_, -1.0, Y, X));
    bool ok = false;
    PetscCall(self->alphaAcceptable(self->work_, self->alphaRef_, &ok));
    if (ok) break;
    PetscCall(VecScale(Y, 0.5));
    *changed = PETSC_TRUE;
    ++self->halvings_;
  }
  PetscFunctionReturn(0);
}

// Line searches that extrapolate (l2, cp) can leave the checked segment: re-check the accepted point.
PetscErrorCode NewtonSolver::postCheck(SNESLineSearch ls, Vec X, Vec Y, Vec W, PetscBool *changedY,
                                       PetscBool *changedW, void *ctx) {
  auto *self = static_cast<NewtonSolver *>(ctx);
  PetscFunctionBeginUser;
  *changedY = PETSC_FALSE;
  *changedW = PETSC_FALSE;
  PetscReal lambda;
  PetscCall(SNESLineSearchGetLambda(ls, &lambda));
  for (int k = 0; k < 60; ++k) {
    bool ok = false;
    PetscCall(self->alphaAcceptable(W, self->alphaRef_, &ok));
    if (ok) break;
    lambda *= 0.5;
    PetscCall(VecWAXPY(W, -lambda, Y, X));
    *changedW = PETSC_TRUE;
    ++self->halvings_;
  }
  if (*changedW) PetscCall(SNESLineSearchSetLambda(ls, lambda));
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonSolver::convergenceTest(SNES snes, PetscInt it, PetscReal xnorm, PetscReal snorm,
                                             PetscReal fnorm, SNESConvergedReason *reason, void *ctx) {
  auto *self = static_cast<NewtonSolver *>(ctx);
  PetscFunctionBeginUser;
  PetscCall(SNESConvergedDefault(snes, it, xnorm, snorm, fnorm, reason, nullptr));
  // A short step only means convergence if it is a Newton step: a CG stopped early (iteration limit, or
  // DIVERGED_INDEFINITE_PC from a multigrid smoother) returns a short direction far from the solution.
  KSP ksp;
  KSPConvergedReason linearReason = KSP_CONVERGED_ITERATING;
  PetscCall(SNESGetKSP(snes, &ksp));
  if (it > 0) PetscCall(KSPGetConvergedReason(ksp, &linearReason));
  if (*reason == SNES_CONVERGED_ITERATING && it > 0 && linearReason > 0 && self->lastStepInf_ >= 0.0 &&
      self->lastStepInf_ <= self->stepTol_)
  {
    *reason = SNES_CONVERGED_SNORM_RELATIVE;  // the paper's criterion: |Newton step|_inf <= newton_tol L (dt)
    self->stepCriterion_ = true;
  }
  PetscFunctionReturn(0);
}

// Rigid-body modes of the rest configuration as the Jacobian's near-nullspace (-near_nullspace rigid, the default):
// algebraic multigrid (-pc_type gamg) builds its coarse spaces from them; other preconditioners ignore them.
PetscErrorCode NewtonSolver::attachNearNullSpace() {
  std::string mode = "rigid";
  PetscBool set;
  PetscFunctionBeginUser;
  PetscCall(fem::optionString(nullptr, "-near_nullspace", &mode, &set));
  if (mode == "none") PetscFunctionReturn(0);
  if (mode != "rigid")
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -near_nullspace: '%s' is not rigid|none", mode.c_str());
  const PetscInt bs = disc_->dofsPerVertex();
  PetscInt n;
  PetscCall(VecGetLocalSize(work_, &n));
  Vec coords;
  PetscCall(VecCreateMPI(PetscObjectComm((PetscObject)work_), n, PETSC_DETERMINE, &coords));
  PetscCall(VecSetBlockSize(coords, bs));
  PetscCall(VecSetUp(coords));
  PetscCall(disc_->restPositions(work_));
  PetscCall(VecCopy(work_, coords));
  MatNullSpace nsp;
  PetscCall(MatNullSpaceCreateRigidBody(coords, &nsp));
  PetscCall(MatSetNearNullSpace(J_, nsp));
  PetscCall(MatNullSpaceDestroy(&nsp));
  PetscCall(VecDestroy(&coords));
  PetscFunctionReturn(0);
}

// GAMG keeps its prolongators across Newton iterations (-pc_gamg_reuse_interpolation) and by default also the
// Chebyshev smoothers' eigenvalue bounds estimated with them at the first setup. Newton's Hessians change spectrum
// from one iteration to the next (an inside-out start stiffens by orders of magnitude in the mollifier's blend
// band), so a stale upper bound makes the smoother amplify high modes: CG stops with DIVERGED_INDEFINITE_PC. With
// -pc_gamg_use_sa_esteig false each smoother re-estimates its bounds on the new operator (a few Krylov iterations).
PetscErrorCode NewtonSolver::configureMultigrid() {
  KSP ksp;
  PC pc;
  PetscBool isGamg, userSet;
  const char *prefix;
  PetscFunctionBeginUser;
  PetscCall(SNESGetKSP(snes_, &ksp));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCGAMG, &isGamg));
  if (!isGamg) PetscFunctionReturn(0);
  PetscCall(PCGetOptionsPrefix(pc, &prefix));
  PetscCall(PetscOptionsHasName(nullptr, prefix, "-pc_gamg_use_sa_esteig", &userSet));
  if (!userSet) PetscCall(PCGAMGSetUseSAEstEig(pc, PETSC_FALSE));
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonSolver::setup(fem::Discretization &disc, bool dynamic, double dt) {
  MPI_Comm comm;
  PetscFunctionBeginUser;
  disc_ = &disc;
  DM dm = disc.dm();
  PetscCall(PetscObjectGetComm((PetscObject)dm, &comm));
  PetscCall(PetscLogStageGetId("assembly", &assemblyStage_));
  if (assemblyStage_ < 0) PetscCall(PetscLogStageRegister("assembly", &assemblyStage_));

  PetscReal newtonTol = dynamic ? 1e-2 : 1e-4;
  PetscBool set;
  PetscCall(fem::optionReal(nullptr, "-newton_tol", &newtonTol, &set));
  if (!(newtonTol > 0.0))
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -newton_tol must be > 0 (got %g)", (double)newtonTol);
  stepTol_ = newtonTol * disc.mesh().diagonal * (dynamic ? dt : 1.0);
  PetscCall(fem::optionReal(nullptr, "-alpha_min", &alphaMin_, &set));
  if (!(alphaMin_ >= 0.0))
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -alpha_min must be >= 0 (got %g)", (double)alphaMin_);

  PetscCall(SNESCreate(comm, &snes_));
  PetscCall(SNESSetDM(snes_, dm));
  PetscCall(SNESSetType(snes_, SNESNEWTONLS));
  PetscCall(DMSNESSetBoundaryLocal(dm, boundaryLocal, this));
  PetscCall(DMSNESSetFunctionLocal(dm, functionLocal, this));
  PetscCall(DMSNESSetJacobianLocal(dm, jacobianLocal, this));
  PetscCall(SNESSetObjective(snes_, objectiveCallback, this));
  std::string matType;  // the discretization asks for BAIJ (bs = dofs per vertex); GAMG in PETSc 3.18 needs AIJ
  PetscCall(fem::optionString(nullptr, "-dm_mat_type", &matType, &set));
  if (set) PetscCall(DMSetMatType(dm, matType.c_str()));
  PetscCall(DMCreateMatrix(dm, &J_));
  PetscCall(MatSetOption(J_, MAT_SYMMETRIC, PETSC_TRUE));
  if (disc.couplesBeyondCells()) PetscCall(MatSetOption(J_, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_FALSE));
  PetscCall(SNESSetJacobian(snes_, J_, J_, nullptr, nullptr));
  PetscCall(DMCreateGlobalVector(dm, &work_));
  PetscCall(attachNearNullSpace());

  // Defaults (overridable by -snes_*, -ksp_*, -pc_*).
  // stol = 0: a step shortened by the alpha safeguard must not read as convergence (the paper's criterion is
  // on the full Newton direction, see convergenceTest).
  PetscCall(SNESSetTolerances(snes_, PETSC_DEFAULT, 1e-8, 0.0, 500, PETSC_DEFAULT));
  PetscCall(SNESSetMaxLinearSolveFailures(snes_, PETSC_MAX_INT));  // an unconverged CG direction is still tried
  KSP ksp;
  PC pc;
  PetscCall(SNESGetKSP(snes_, &ksp));
  PetscCall(KSPSetType(ksp, KSPCG));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCSetType(pc, PCJACOBI));
  PetscCall(KSPSetTolerances(ksp, 1e-6, PETSC_DEFAULT, PETSC_DEFAULT, 10000));
  SNESLineSearch ls;
  PetscCall(SNESGetLineSearch(snes_, &ls));
  PetscCall(SNESLineSearchSetType(ls, SNESLINESEARCHBT));
  PetscCall(SNESSetConvergenceTest(snes_, convergenceTest, this, nullptr));
  PetscCall(SNESSetFromOptions(snes_));
  PetscCall(configureMultigrid());
  // Hooks after SetFromOptions so a user-chosen line search type keeps them.
  PetscCall(SNESGetLineSearch(snes_, &ls));
  PetscCall(SNESLineSearchSetPreCheck(ls, preCheck, this));
  PetscCall(SNESLineSearchSetPostCheck(ls, postCheck, this));
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonSolver::solve(Vec x, NewtonResult *result) {
  PetscFunctionBeginUser;
  halvings_ = 0;
  lastStepInf_ = -1.0;
  stepCriterion_ = false;
  KSP ksp;
  PetscInt kspBefore, kspAfter;
  PetscCall(SNESGetKSP(snes_, &ksp));
  PetscCall(KSPGetTotalIterations(ksp, &kspBefore));
  PetscCall(SNESSolve(snes_, nullptr, x));
  PetscCall(KSPGetTotalIterations(ksp, &kspAfter));
  PetscCall(SNESGetIterationNumber(snes_, &result->newtonIterations));
  PetscCall(SNESGetFunctionNorm(snes_, &result->residualNorm));
  result->linearIterations = kspAfter - kspBefore;  // SNES keeps a stale count when it converges at iteration 0
  PetscCall(SNESGetConvergedReason(snes_, &result->reason));
  result->safeguardHalvings = halvings_;
  result->stepCriterion = stepCriterion_;
  halvingsTotal_ += halvings_;
  PetscFunctionReturn(0);
}

}  // namespace aries::solver
