#include "solver/newton.hpp"

#include "core/options.hpp"
#include "solver/solver_options.hpp"

#include <string>

// Setup, options and the solve loop of the projected Newton solver (newton.hpp); one iteration's callbacks, the
// safeguard, the convergence tests and the subspace step are in newton_iteration.cpp.
namespace aries::solver {

NewtonResult &NewtonResult::operator+=(const NewtonResult &o) {
  newtonIterations += o.newtonIterations;
  linearSolves += o.linearSolves;
  linearIterations += o.linearIterations;
  linearAtLimit += o.linearAtLimit;
  safeguardHalvings += o.safeguardHalvings;
  reason = o.reason;
  // A part that converged without an update (a load sub-step, the supported phase after a detached start) after
  // parts that did update: the step as a whole converged by the Newton step criterion.
  const bool updatedBefore = newtonIterations > o.newtonIterations;
  convergence = o.convergence == Convergence::Initial && updatedBefore ? Convergence::NewtonStep : o.convergence;
  residualNorm = o.residualNorm;
  barrierFallbackCells = std::max(barrierFallbackCells, o.barrierFallbackCells);
  barrierActiveCells = std::max(barrierActiveCells, o.barrierActiveCells);
  history.insert(history.end(), o.history.begin(), o.history.end());
  return *this;
}

const char *filterModeName(EigenFilterMode m) {
  switch (m) {
    case EigenFilterMode::Clamp: return "clamp";
    case EigenFilterMode::Abs: return "abs";
    case EigenFilterMode::Adaptive: return "adaptive";
    case EigenFilterMode::None: return "none";
  }
  return "?";
}

std::string reasonName(const NewtonResult &r) {
  if (r.reason > 0) switch (r.convergence) {
      case Convergence::Initial: return "converged_initial";
      case Convergence::NewtonStep: return "newton_step";
      case Convergence::StepBound: return "step_bound";
      case Convergence::EnergyRoundoff: return "energy_roundoff";
      case Convergence::None:
      case Convergence::Petsc: break;
    }
  switch (r.reason) {
    case SNES_CONVERGED_FNORM_ABS: return "fnorm_abs";
    case SNES_CONVERGED_FNORM_RELATIVE: return "fnorm_rel";
    case SNES_CONVERGED_SNORM_RELATIVE: return "snorm_rel";
    case SNES_CONVERGED_ITS: return "its";
    case SNES_DIVERGED_FUNCTION_DOMAIN: return "diverged_domain";
    case SNES_DIVERGED_FUNCTION_COUNT: return "diverged_function_count";
    case SNES_DIVERGED_LINEAR_SOLVE: return "diverged_linear_solve";
    case SNES_DIVERGED_FNORM_NAN: return "diverged_nan";
    case SNES_DIVERGED_MAX_IT: return "diverged_max_it";
    case SNES_DIVERGED_LINE_SEARCH: return "diverged_line_search";
    case SNES_DIVERGED_LOCAL_MIN: return "diverged_local_min";
    case SNES_DIVERGED_DTOL: return "diverged_dtol";
    default: return "reason_" + std::to_string(static_cast<int>(r.reason));
  }
}

NewtonSolver::~NewtonSolver() {
  if (snes_) SNESDestroy(&snes_);
  if (J_) MatDestroy(&J_);
  for (Vec *v : {&work_, &invMass_, &prevX_, &newtonDir_})
    if (*v) VecDestroy(v);
  for (Vec &v : history_) VecDestroy(&v);
  if (defaultKspCtx_) KSPConvergedDefaultDestroy(defaultKspCtx_);
}

// ---- setup --------------------------------------------------------------------------------------------------------

// Rigid-body modes of the rest configuration as the Jacobian's near-nullspace (-near_nullspace rigid, the default):
// algebraic multigrid (-pc_type gamg) builds its coarse spaces from them; other preconditioners ignore them.
PetscErrorCode NewtonSolver::attachNearNullSpace() {
  PetscFunctionBeginUser;
  if (nearNullspace_ == 1) PetscFunctionReturn(0);  // rigid|none
  MatNullSpace nsp;
  PetscCall(disc_->restPositions(work_));
  PetscCall(rigidBodyModes(work_, disc_->dofsPerVertex(), &nsp));
  PetscCall(MatSetNearNullSpace(J_, nsp));
  PetscCall(MatNullSpaceDestroy(&nsp));
  PetscFunctionReturn(0);
}

PetscErrorCode rigidBodyModes(Vec positions, PetscInt dofsPerVertex, MatNullSpace *modes) {
  Vec coords;  // a copy carrying the block size the rigid-body null space reads the dimension from
  PetscInt n;
  PetscFunctionBeginUser;
  PetscCall(VecGetLocalSize(positions, &n));
  PetscCall(VecCreateMPI(PetscObjectComm((PetscObject)positions), n, PETSC_DETERMINE, &coords));
  PetscCall(VecSetBlockSize(coords, dofsPerVertex));
  PetscCall(VecSetUp(coords));
  PetscCall(VecCopy(positions, coords));
  PetscCall(MatNullSpaceCreateRigidBody(coords, modes));
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

PetscErrorCode NewtonSolver::setTimeStep(double dt) {
  PetscFunctionBeginUser;
  dt_ = dt;
  stepTol_ = newtonTol_ * disc_->mesh().diagonal * (dynamic_ ? dt : 1.0);
  PetscFunctionReturn(0);
}

kernels::EigenFilter NewtonSolver::initialFilter() const {
  switch (filterMode_) {
    case EigenFilterMode::Clamp: return kernels::EigenFilter::Clamp;
    case EigenFilterMode::None: return kernels::EigenFilter::None;
    case EigenFilterMode::Abs:
    case EigenFilterMode::Adaptive: return kernels::EigenFilter::Abs;  // adaptive: no model to judge yet
  }
  return kernels::EigenFilter::Clamp;
}

// Defaults chosen by measurement (docs/results.md): backward Euler clamps (inertia keeps the system definite, and
// clamping leaves the inverted elements' soft modes soft), static solves take absolute values (no inertia: clamped
// Hessians of a scrambled body are near-singular); the subspace step is unlimited with inertia and limited to twice
// the Newton step, after full steps only, without it (a static solve from a scramble can otherwise jump into another
// basin, e.g. a folded body).
PetscErrorCode NewtonSolver::readOptions(bool dynamic, const NewtonSolver *base, const char *prefix) {
  const core::ReadContext at{prefix, dynamic ? "beuler" : "static", base != nullptr};
  PetscFunctionBeginUser;
  if (base) {  // start from the base solver's values; the prefixed options override them
    newtonTol_ = base->newtonTol_;
    alphaMin_ = base->alphaMin_;
    filterMode_ = base->filterMode_;
    analyticEigensystem_ = base->analyticEigensystem_;
    adaptiveTol_ = base->adaptiveTol_;
    subspace_ = base->subspace_;
    subspaceMax_ = base->subspaceMax_;
    rotation_ = base->rotation_;
    forcing_ = base->forcing_;
    nearNullspace_ = base->nearNullspace_;
  }
  PetscCall(core::get(opt::newtonTol, &newtonTol_, nullptr, at));
  PetscCall(core::get(opt::alphaMin, &alphaMin_, nullptr, at));
  PetscCall(core::getChoice(opt::psdProjection, &filterMode_, nullptr, at));
  int eigensystem = analyticEigensystem_ ? 0 : 1;  // analytic|numeric
  PetscCall(core::getChoice(opt::psdEigensystem, &eigensystem, nullptr, at));
  analyticEigensystem_ = eigensystem == 0;
  if (filterMode_ == EigenFilterMode::Adaptive) PetscCall(core::get(opt::psdAdaptiveTol, &adaptiveTol_, nullptr, at));
  PetscCall(core::get(opt::newtonSubspace, &subspace_, nullptr, at));
  if (subspace_ > 0) {
    PetscCall(core::get(opt::newtonSubspaceMax, &subspaceMax_, nullptr, at));
    if (subspaceMax_ > 0.0 && subspaceMax_ < 1.0)
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -newton_subspace_max must be 0 (no limit) or >= 1 (got %g)",
              subspaceMax_);
  }
  PetscCall(core::get(opt::newtonRotation, &rotation_, nullptr, at));
  PetscCall(core::get(opt::newtonForcing, &forcing_, nullptr, at));
  PetscBool guess = PETSC_FALSE;
  if (dynamic) PetscCall(core::get(opt::newtonInertiaGuess, &guess, nullptr, at));
  useInertiaGuess_ = guess;
  PetscCall(core::getChoice(opt::nearNullspace, &nearNullspace_, nullptr, at));
  PetscFunctionReturn(0);
}

// The base solver's PETSc settings that SNESSetFromOptions would otherwise leave at aries' defaults for a prefixed
// solver: SNES tolerances, line search type, KSP type and tolerances, PC type. Type-specific options (-pc_gamg_*,
// -ksp_cg_type, ...) apply to the prefixed solver only when given with its prefix.
PetscErrorCode NewtonSolver::copySolverSettings(const NewtonSolver &base) {
  PetscReal atol, rtol, stol, krtol, kabstol, kdtol;
  PetscInt maxit, maxf, kmaxit;
  SNESLineSearch ls, baseLs;
  SNESLineSearchType lsType;
  KSP ksp, baseKsp;
  KSPType kspType;
  PC pc, basePc;
  PCType pcType;
  PetscFunctionBeginUser;
  PetscCall(SNESGetTolerances(base.snes_, &atol, &rtol, &stol, &maxit, &maxf));
  PetscCall(SNESSetTolerances(snes_, atol, rtol, stol, maxit, maxf));
  PetscCall(SNESGetLineSearch(base.snes_, &baseLs));
  PetscCall(SNESLineSearchGetType(baseLs, &lsType));
  PetscCall(SNESGetLineSearch(snes_, &ls));
  PetscCall(SNESLineSearchSetType(ls, lsType));
  PetscCall(SNESGetKSP(base.snes_, &baseKsp));
  PetscCall(SNESGetKSP(snes_, &ksp));
  PetscCall(KSPGetType(baseKsp, &kspType));
  PetscCall(KSPSetType(ksp, kspType));
  PetscCall(KSPGetTolerances(baseKsp, &krtol, &kabstol, &kdtol, &kmaxit));
  PetscCall(KSPSetTolerances(ksp, krtol, kabstol, kdtol, kmaxit));
  PetscCall(KSPGetPC(baseKsp, &basePc));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCGetType(basePc, &pcType));
  PetscCall(PCSetType(pc, pcType));
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonSolver::setup(fem::Discretization &disc, bool dynamic, double dt, const NewtonSolver *base,
                                   const char *prefix) {
  MPI_Comm comm;
  PetscBool set;
  PetscFunctionBeginUser;
  disc_ = &disc;
  dynamic_ = dynamic;
  DM dm = disc.dm();
  PetscCall(PetscObjectGetComm((PetscObject)dm, &comm));
  PetscCall(PetscLogStageGetId("assembly", &assemblyStage_));
  if (assemblyStage_ < 0) PetscCall(PetscLogStageRegister("assembly", &assemblyStage_));
  PetscCall(readOptions(dynamic, base, prefix));
  PetscCall(setTimeStep(dt));

  PetscCall(SNESCreate(comm, &snes_));
  if (prefix) PetscCall(SNESSetOptionsPrefix(snes_, prefix));
  PetscCall(SNESSetDM(snes_, dm));
  PetscCall(SNESSetType(snes_, SNESNEWTONLS));
  PetscCall(DMSNESSetBoundaryLocal(dm, boundaryLocal, this));
  PetscCall(DMSNESSetFunctionLocal(dm, functionLocal, this));
  PetscCall(DMSNESSetJacobianLocal(dm, jacobianLocal, this));
  PetscCall(SNESSetObjective(snes_, objectiveCallback, this));
  std::string matType;  // the discretization asks for BAIJ (bs = dofs per vertex); GAMG in PETSc 3.18 needs AIJ
  PetscCall(core::optionString(nullptr, "-dm_mat_type", &matType, &set));
  if (set) PetscCall(DMSetMatType(dm, matType.c_str()));
  PetscCall(DMCreateMatrix(dm, &J_));
  PetscCall(MatSetOption(J_, MAT_SYMMETRIC, PETSC_TRUE));
  PetscBool symmetricStorage;  // SBAIJ keeps the upper triangle: the element blocks below the diagonal are dropped
  PetscCall(PetscObjectTypeCompareAny((PetscObject)J_, &symmetricStorage, MATSBAIJ, MATSEQSBAIJ, MATMPISBAIJ, ""));
  if (symmetricStorage) PetscCall(MatSetOption(J_, MAT_IGNORE_LOWER_TRIANGULAR, PETSC_TRUE));
  PetscCall(SNESSetJacobian(snes_, J_, J_, nullptr, nullptr));
  PetscCall(DMCreateGlobalVector(dm, &work_));
  PetscCall(VecDuplicate(work_, &prevX_));
  PetscCall(VecDuplicate(work_, &newtonDir_));
  history_.resize(subspace_);
  for (Vec &v : history_) PetscCall(VecDuplicate(work_, &v));
  PetscCall(attachNearNullSpace());
  if (dynamic) {  // 1 / m per free dof (step bound, inertia guess) and the smallest mass
    PetscReal mmin;
    PetscCall(VecDuplicate(work_, &invMass_));
    PetscCall(disc.lumpedMass(invMass_));
    PetscCall(VecMin(invMass_, nullptr, &mmin));
    minMass_ = mmin;
    PetscCall(VecReciprocal(invMass_));
  }

  // Defaults (overridable by -snes_*, -ksp_*, -pc_*).
  // rtol = 0: a residual small relative to the initial one is not equilibrium (a scrambled start has a huge one).
  // stol = 0: a step shortened by the alpha safeguard must not read as convergence.
  PetscCall(SNESSetTolerances(snes_, 0.0, 0.0, 0.0, 500, PETSC_DEFAULT));
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
  if (base) PetscCall(copySolverSettings(*base));
  PetscCall(SNESSetFromOptions(snes_));
  PetscCall(KSPGetTolerances(ksp, &baseRtol_, nullptr, nullptr, nullptr));
  PetscCall(KSPConvergedDefaultCreate(&defaultKspCtx_));
  PetscCall(KSPSetConvergenceTest(ksp, linearConvergence, this, nullptr));
  PetscCall(configureMultigrid());
  // Hooks after SetFromOptions so a user-chosen line search type keeps them.
  PetscCall(SNESGetLineSearch(snes_, &ls));
  PetscCall(SNESLineSearchSetPreCheck(ls, preCheck, this));
  PetscCall(SNESLineSearchSetPostCheck(ls, postCheck, this));
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonSolver::solve(Vec x, NewtonResult *result) {
  KSP ksp;
  PetscInt kspBefore, kspAfter;
  PetscFunctionBeginUser;
  cur_ = NewtonResult{};
  havePending_ = false;
  historyCount_ = 0;
  lastFull_ = false;
  disc_->setEigenFilter(initialFilter());
  disc_->setAnalyticEigensystem(analyticEigensystem_);
  PetscCall(SNESGetKSP(snes_, &ksp));
  PetscCall(KSPGetTotalIterations(ksp, &kspBefore));
  PetscCall(SNESSolve(snes_, nullptr, x));
  PetscCall(KSPGetTotalIterations(ksp, &kspAfter));
  Vec g;  // the residual after the final correction (SNES keeps the norm from before it)
  PetscCall(SNESGetFunction(snes_, &g, nullptr, nullptr));
  PetscCall(VecNorm(g, NORM_2, &cur_.residualNorm));
  cur_.linearIterations = kspAfter - kspBefore;  // SNES keeps a stale count when it converges at iteration 0
  PetscCall(SNESGetConvergedReason(snes_, &cur_.reason));
  if (cur_.reason <= 0) cur_.convergence = Convergence::None;
  if (havePending_) {  // the last line search failed: keep its record
    cur_.history.push_back(pending_);
    havePending_ = false;
  }
  *result = cur_;
  halvingsTotal_ += cur_.safeguardHalvings;
  PetscFunctionReturn(0);
}

}  // namespace aries::solver
