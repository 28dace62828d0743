#include "solver/newton.hpp"

#include "core/options.hpp"
#include "solver/local_vec.hpp"

#include <algorithm>
#include <string>

// Setup and the solve of the projected Newton solver (newton.hpp); the model callbacks and the hooks that run the
// strategies around each line search are in newton_iteration.cpp, each strategy in its own *_step.cpp.
namespace aries::solver {

NewtonResult &NewtonResult::operator+=(const NewtonResult &o) {
  newtonIterations += o.newtonIterations;
  linearSolves += o.linearSolves;
  linearIterations += o.linearIterations;
  linearAtLimit += o.linearAtLimit;
  localIterations += o.localIterations;
  safeguardHalvings += o.safeguardHalvings;
  reason = o.reason;
  // A part that converged without an update (a load sub-step, the supported phase after a detached start) after
  // parts that did update: the step as a whole converged by the Newton step criterion.
  const bool updatedBefore = newtonIterations > o.newtonIterations;
  convergence = o.convergence == Convergence::Initial && updatedBefore ? Convergence::NewtonStep : o.convergence;
  residualNorm = o.residualNorm;
  assemblySeconds += o.assemblySeconds;
  barrierFallbackCells = std::max(barrierFallbackCells, o.barrierFallbackCells);
  barrierActiveCells = std::max(barrierActiveCells, o.barrierActiveCells);
  history.insert(history.end(), o.history.begin(), o.history.end());
  return *this;
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
  steps_.clear();  // before the SNES: the convergence check holds its KSP test's context
  if (ctx_.snes) SNESDestroy(&ctx_.snes);
  if (ctx_.J) MatDestroy(&ctx_.J);
  if (local_.ksp) KSPDestroy(&local_.ksp);
  for (Vec *v : {&ctx_.work, &ctx_.invMass, &ctx_.trialX, &ctx_.trialF, &lift_.rhs, &lift_.step, &lift_.trial,
                 &lift_.coupling, &local_.before})
    if (*v) VecDestroy(v);
}

// ---- setup --------------------------------------------------------------------------------------------------------

// Rigid-body modes of the rest configuration as the Jacobian's near-nullspace (-near_nullspace rigid, the default):
// algebraic multigrid (-pc_type gamg) builds its coarse spaces from them; other preconditioners ignore them.
PetscErrorCode NewtonSolver::attachNearNullSpace() {
  PetscInt bs;
  PetscFunctionBeginUser;
  if (!opts_.rigidNearNullspace) PetscFunctionReturn(0);
  MatNullSpace nsp;
  PetscCall(MatGetBlockSize(ctx_.J, &bs));
  if (bs == ctx_.disc->dofsPerVertex()) {
    PetscCall(ctx_.disc->restPositions(ctx_.work));
    PetscCall(rigidBodyModes(ctx_.work, ctx_.disc->dofsPerVertex(), &nsp));
  } else {  // vertices held in some components only (-bc_clamp_<id>_components): the modes dof by dof
    PetscCall(rigidBodyModesOfFreeDofs(ctx_.disc->kinematics(), ctx_.disc->dofsPerVertex(), ctx_.work, &nsp));
  }
  PetscCall(MatSetNearNullSpace(ctx_.J, nsp));
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

PetscErrorCode rigidBodyModesOfFreeDofs(const fem::Kinematics &kin, PetscInt dofsPerVertex, Vec like,
                                        MatNullSpace *modes) {
  const int R = static_cast<int>(dofsPerVertex), n = R == 3 ? 6 : 3;
  Vec v[6];
  PetscInt lo;
  PetscFunctionBeginUser;
  PetscCall(VecGetOwnershipRange(like, &lo, nullptr));
  for (int k = 0; k < n; ++k) {
    PetscScalar *a;
    PetscCall(VecDuplicate(like, &v[k]));
    PetscCall(VecSet(v[k], 0.0));
    PetscCall(VecGetArray(v[k], &a));
    kin.forEachOwnedFreeVertex([&](PetscInt, PetscInt, const PetscInt *rows, const Eigen::Vector3d &X) {
      const Eigen::Vector3d m = fem::rigidMotion(k, R, X);
      for (int i = 0; i < R; ++i)
        if (rows[i] >= 0) a[rows[i] - lo] = m[i];
    });
    PetscCall(VecRestoreArray(v[k], &a));
  }
  for (int k = 0; k < n; ++k) {  // Gram-Schmidt, twice: MatNullSpaceCreate wants an orthonormal set
    for (int pass = 0; pass < 2; ++pass)
      for (int j = 0; j < k; ++j) {
        PetscScalar dot;
        PetscCall(VecDot(v[k], v[j], &dot));
        PetscCall(VecAXPY(v[k], -dot, v[j]));
      }
    PetscCall(VecNormalize(v[k], nullptr));
  }
  PetscCall(MatNullSpaceCreate(PetscObjectComm((PetscObject)like), PETSC_FALSE, n, v, modes));
  for (int k = 0; k < n; ++k) PetscCall(VecDestroy(&v[k]));
  PetscFunctionReturn(0);
}

// An option of this solver's GAMG that aries chooses unless the user gave it (-<prefix>name): set, and read back at
// once so that it is never reported as unused (GAMG reads it only at its first setup). *chosen (optional): aries set
// it.
static PetscErrorCode chooseMultigridOption(const char *prefix, const char *name, const char *value, bool *chosen) {
  const std::string option = std::string("-") + (prefix ? prefix : "") + name;
  PetscBool given = PETSC_FALSE;
  char read[64];
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsHasName(nullptr, nullptr, option.c_str(), &given));
  if (chosen) *chosen = !given;
  if (given) PetscFunctionReturn(0);
  PetscCall(PetscOptionsSetValue(nullptr, option.c_str(), value));
  PetscCall(PetscOptionsGetString(nullptr, nullptr, option.c_str(), read, sizeof(read), nullptr));
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
  PetscCall(SNESGetKSP(ctx_.snes, &ksp));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCGAMG, &isGamg));
  if (!isGamg) PetscFunctionReturn(0);
  PetscCall(PCGetOptionsPrefix(pc, &prefix));
  PetscCall(PetscOptionsHasName(nullptr, prefix, "-pc_gamg_use_sa_esteig", &userSet));
  if (!userSet) PetscCall(PCGAMGSetUseSAEstEig(pc, PETSC_FALSE));
  PetscFunctionReturn(0);
}

// Supports that leave a rigid motion free (rollers or symmetry planes only, e.g. a block between two faces held in z
// alone: x, y and the turn about z are free) make the static Hessian singular along that motion. CG solves the
// consistent system, but GAMG's near-nullspace holds the motion exactly, so its coarse operator is singular too and
// the default coarse LU returns garbage along it: the test cube between two such faces ended step 1 with
// diverged_line_search on 1 and 2 ranks (29 updates, the residual at 7e-11 but the Newton step never small). The
// coarse solve by the pseudo-inverse (PCSVD of the coarsest grid, which is small) drops that component: 2 and 3 updates
// per step, as Jacobi takes. Static GAMG solves only (inertia makes the Hessian definite); a user
// -mg_coarse_pc_type chooses. Collective.
PetscErrorCode NewtonSolver::solveCoarseSingularSystem(const char *prefix) {
  PetscInt freeRigid = 0;
  bool chosen = false;
  PetscFunctionBeginUser;
  PetscCall(ctx_.disc->kinematics().freeRigidMotions(&freeRigid));
  if (freeRigid == 0) PetscFunctionReturn(0);
  PetscCall(chooseMultigridOption(prefix, "mg_coarse_pc_type", PCSVD, &chosen));
  if (!chosen) PetscFunctionReturn(0);
  PetscCall(PetscPrintf(PetscObjectComm((PetscObject)ctx_.work),
                        "aries: GAMG's coarse solve is the pseudo-inverse (-%smg_coarse_pc_type svd): the supports "
                        "leave %d rigid motion(s) free, along which the static Hessian is singular\n",
                        prefix ? prefix : "", (int)freeRigid));
  PetscFunctionReturn(0);
}

// The preconditioner when -pc_type is not given (docs/options.md, "The preconditioner rule"; measured by
// bench/scale_out.py): on a static system CG + Jacobi's iterations grow with 1/h and GAMG's do not, but a GAMG
// iteration costs about eight Jacobi ones (its share of the rebuilds included) and the AIJ assembly is slower: level
// at 43k free dofs on the cube, ahead from 197k on. A static solve with at least -multigrid_min_dofs free dofs gets
// GAMG (smoothed aggregation, the rigid near-nullspace, AIJ, kept across Newton systems while its solves stay fast:
// -multigrid_reuse_growth); everything else the paper's CG + Jacobi, and so does a dynamic solve at any size: the
// inertia term keeps Jacobi's iterations low and makes the Hessian too diagonally dominant for GAMG's aggregation. A user
// -dm_mat_type other than AIJ keeps Jacobi (GAMG in PETSc 3.18 cannot coarsen BAIJ). One exception to Jacobi: backward
// Euler from a scramble, invert or collapse start of a 3D solid with fiber terms (NewtonOptions::fiberDegenerateStart)
// gets point-block Jacobi (each vertex's 3 x 3 diagonal block inverted), without a user -dm_mat_type: there the
// volume term's lambda cof F (x) cof F and the fibers' a (x) a couple a vertex's components far beyond the mass term
// in the stretched cells; Jacobi's CG ended at -ksp_max_it in 48 solves of 27 fiber scrambles, point-block Jacobi's in
// 3, at 0.65-0.97x the time (bench/results/degenerate_starts_pbjacobi.md; ortho lost there, 0.95-1.57x). A static
// GAMG solve (by the rule or a user -pc_type gamg) whose supports leave a rigid motion free gets the pseudo-inverse as
// its coarse solve (solveCoarseSingularSystem).
PetscErrorCode NewtonSolver::choosePreconditioner(bool dynamic, bool matTypeGiven, bool aij, const char *prefix) {
  std::string pcType;
  PetscBool pcSet = PETSC_FALSE;
  PetscInt freeDofs;
  PetscFunctionBeginUser;
  PetscCall(core::optionString(prefix, "-pc_type", &pcType, &pcSet));
  PetscCall(VecGetSize(ctx_.work, &freeDofs));
  const PetscInt minDofs = opts_.multigridMinDofs;
  multigridByRule_ = !pcSet && !(matTypeGiven && !aij) && !dynamic && minDofs >= 0 && freeDofs >= minDofs;
  pointBlockByRule_ = !pcSet && !matTypeGiven && dynamic && opts_.fiberDegenerateStart;
  if (pointBlockByRule_)
    PetscCall(PetscPrintf(PetscObjectComm((PetscObject)ctx_.work),
                          "aries: linear solver CG + point-block Jacobi (backward Euler from a degenerate start with "
                          "fiber terms; -pc_type jacobi for the paper's CG + Jacobi)\n"));
  if (multigridByRule_)
    PetscCall(PetscPrintf(PetscObjectComm((PetscObject)ctx_.work),
                          "aries: linear solver CG + GAMG (a static solve of %d free DoFs, -multigrid_min_dofs %d; "
                          "-pc_type jacobi for the paper's CG + Jacobi)\n",
                          (int)freeDofs, (int)minDofs));
  if (multigridByRule_ || (!dynamic && pcSet && pcType == PCGAMG)) PetscCall(solveCoarseSingularSystem(prefix));
  PetscFunctionReturn(0);
}

// A floating body's Hessian is singular: the rigid motions have no energy (no supports, no inertia in a static
// solve). CG + Jacobi solves such a consistent system (the rigid-motion removal step drops the direction's rigid
// share), but GAMG, built on those very motions as its near-nullspace, gets a singular coarse problem: in the
// detached start of a static scramble every one of its CG solves ended DIVERGED_DTOL or INDEFINITE_PC, the stage
// could not certify convergence and handed the supported solve the scrambled start (homer and bull, scramble and
// inside out, nu 0.3 and 0.45: 4 of 8 runs ended away from rest, at 7x the updates; bench/results/
// degenerate_starts_static_gamg.md). So a floating solver that would inherit GAMG from the main solver (by the rule
// or a user -pc_type gamg) gets Jacobi; -<prefix>pc_type still chooses (read by SNESSetFromOptions after this).
PetscErrorCode NewtonSolver::avoidMultigridWhenFloating(PC pc, const char *prefix) {
  PetscBool gamg, own = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCGAMG, &gamg));
  if (prefix) PetscCall(PetscOptionsHasName(nullptr, prefix, "-pc_type", &own));
  if (!gamg || own) PetscFunctionReturn(0);
  PetscCall(PCSetType(pc, PCJACOBI));
  PetscCall(PetscPrintf(PetscObjectComm((PetscObject)pc),
                        "aries: the %s solve (a body without supports, a singular Hessian) uses CG + Jacobi, not the "
                        "main solve's GAMG (-%spc_type to choose)\n",
                        prefix ? prefix : "floating", prefix ? prefix : ""));
  PetscFunctionReturn(0);
}

// The matrix type: -dm_mat_type if given, else the discretization's BAIJ (bs = dofs per vertex), except that GAMG (by
// the rule, or -pc_type gamg for this solver or the base solver it copies, but not for a floating solver, which does
// not inherit GAMG) gets AIJ: PETSc 3.18's GAMG cannot coarsen BAIJ, and -pc_type gamg with another -dm_mat_type is a
// one-line error.
PetscErrorCode NewtonSolver::chooseMatrixType(DM dm, const NewtonSolver *base, bool dynamic, const char *prefix,
                                              bool floating) {
  std::string matType;
  PetscBool set = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCall(core::optionString(nullptr, "-dm_mat_type", &matType, &set));
  bool gamgAsked = false;
  const char *prefixes[] = {nullptr, prefix};  // the unprefixed option, then this solver's own (if it has a prefix)
  for (int k = floating && prefix ? 1 : 0; k < (prefix ? 2 : 1); ++k) {
    std::string pcType;
    PetscBool pcSet = PETSC_FALSE;
    PetscCall(core::optionString(prefixes[k], "-pc_type", &pcType, &pcSet));
    gamgAsked = gamgAsked || (pcSet && pcType == PCGAMG);
  }
  const bool aij = matType == MATAIJ || matType == MATSEQAIJ || matType == MATMPIAIJ;
  if (gamgAsked && set && !aij)
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
            "option -pc_type gamg: PETSc 3.18's GAMG cannot coarsen -dm_mat_type %s matrices; give -dm_mat_type aij or "
            "leave -dm_mat_type out (GAMG then gets AIJ)",
            matType.c_str());
  if (base) multigridByRule_ = base->multigridByRule_ && !floating, pointBlockByRule_ = base->pointBlockByRule_;
  else PetscCall(choosePreconditioner(dynamic, set, aij, prefix));
  if (set) PetscCall(DMSetMatType(dm, matType.c_str()));
  else if (multigridByRule_ || gamgAsked) PetscCall(DMSetMatType(dm, MATAIJ));
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonSolver::setTimeStep(double dt) {
  PetscFunctionBeginUser;
  ctx_.dt = dt;
  ctx_.stepTol = std::max(stepTolLoosened_,
                          opts_.convergence.tol * ctx_.disc->mesh().diagonal * (ctx_.dynamic ? dt : 1.0));
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonSolver::loosenStepTolerance(double stepTol) {
  PetscFunctionBeginUser;
  stepTolLoosened_ = std::max(stepTol, 0.0);
  PetscCall(setTimeStep(ctx_.dt));
  PetscFunctionReturn(0);
}

void NewtonSolver::overrideFilter(EigenFilterMode mode) {
  if (!filter_ || opts_.filter.mode == EigenFilterMode::None) return;
  filter_->setMode(mode);
  filterOverride_ = static_cast<int>(mode);
}

void NewtonSolver::restoreFilter() {
  if (filter_) filter_->setMode(opts_.filter.mode);
  filterOverride_ = -1;
}

void NewtonSolver::energyChanged() {
  if (filter_) filter_->energyChanged();
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
  PetscCall(SNESGetTolerances(base.ctx_.snes, &atol, &rtol, &stol, &maxit, &maxf));
  PetscCall(SNESSetTolerances(ctx_.snes, atol, rtol, stol, maxit, maxf));
  PetscCall(SNESGetLineSearch(base.ctx_.snes, &baseLs));
  PetscCall(SNESLineSearchGetType(baseLs, &lsType));
  PetscCall(SNESGetLineSearch(ctx_.snes, &ls));
  PetscCall(SNESLineSearchSetType(ls, lsType));
  PetscCall(SNESGetKSP(base.ctx_.snes, &baseKsp));
  PetscCall(SNESGetKSP(ctx_.snes, &ksp));
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

PetscErrorCode NewtonSolver::setup(fem::Discretization &disc, const NewtonOptions &options, bool dynamic, double dt,
                                   const NewtonSolver *base, const char *prefix, bool floating) {
  MPI_Comm comm;
  PetscFunctionBeginUser;
  opts_ = options;
  ctx_.inertiaGuess = options.inertiaGuess;
  ctx_.disc = &disc;
  ctx_.dynamic = dynamic;
  ctx_.psdHessian = options.filter.mode != EigenFilterMode::None;
  DM dm = disc.dm();
  PetscCall(PetscObjectGetComm((PetscObject)dm, &comm));
  PetscCall(PetscLogStageGetId("assembly", &ctx_.assemblyStage));
  if (ctx_.assemblyStage < 0) PetscCall(PetscLogStageRegister("assembly", &ctx_.assemblyStage));
  PetscCall(setTimeStep(dt));

  PetscCall(SNESCreate(comm, &ctx_.snes));
  SNES snes = ctx_.snes;
  if (prefix) PetscCall(SNESSetOptionsPrefix(snes, prefix));
  PetscCall(SNESSetDM(snes, dm));
  PetscCall(SNESSetType(snes, SNESNEWTONLS));
  PetscCall(DMSNESSetBoundaryLocal(dm, boundaryLocal, this));
  PetscCall(DMSNESSetFunctionLocal(dm, functionLocal, this));
  PetscCall(DMSNESSetJacobianLocal(dm, jacobianLocal, this));
  PetscCall(SNESSetObjective(snes, objectiveCallback, this));
  PetscCall(DMCreateGlobalVector(dm, &ctx_.work));
  PetscCall(chooseMatrixType(dm, base, dynamic, prefix, floating));
  PetscCall(DMSetMatrixPreallocateSkip(dm, PETSC_TRUE));  // the terms preallocate it (Discretization::preallocateHessian)
  PetscCall(DMCreateMatrix(dm, &ctx_.J));
  Mat J = ctx_.J;
  PetscCall(disc.preallocateHessian(J));
  PetscCall(MatSetOption(J, MAT_SYMMETRIC, PETSC_TRUE));
  PetscBool symmetricStorage;  // SBAIJ keeps the upper triangle: the element blocks below the diagonal are dropped
  PetscCall(PetscObjectTypeCompareAny((PetscObject)J, &symmetricStorage, MATSBAIJ, MATSEQSBAIJ, MATMPISBAIJ, ""));
  if (symmetricStorage) PetscCall(MatSetOption(J, MAT_IGNORE_LOWER_TRIANGULAR, PETSC_TRUE));
  PetscCall(SNESSetJacobian(snes, J, J, nullptr, nullptr));
  PetscCall(VecDuplicate(ctx_.work, &ctx_.trialX));
  PetscCall(VecDuplicate(ctx_.work, &ctx_.trialF));
  PetscCall(attachNearNullSpace());
  if (dynamic) {  // 1 / m per free dof (step bound, inertia guess) and the smallest mass
    PetscReal mmin;
    PetscCall(VecDuplicate(ctx_.work, &ctx_.invMass));
    PetscCall(disc.lumpedMass(ctx_.invMass));
    PetscCall(VecMin(ctx_.invMass, nullptr, &mmin));
    ctx_.minMass = mmin;
    PetscCall(VecReciprocal(ctx_.invMass));
  }

  // The strategies, in the order they run (newton_steps.hpp); those the options switch off are not created.
  if (floating) steps_.push_back(std::make_unique<RigidMotionRemoval>());
  auto check = std::make_unique<ConvergenceCheck>(opts_.convergence);
  check_ = check.get();
  steps_.push_back(std::move(check));
  auto safeguard = std::make_unique<AlphaSafeguard>(opts_.safeguard);  // runs last; the subspace step asks it first
  safeguard_ = safeguard.get();
  if (opts_.subspace.size > 0) steps_.push_back(std::make_unique<SubspaceStep>(opts_.subspace, safeguard_));
  if (opts_.rotation.doublings >= 0) steps_.push_back(std::make_unique<RotationalUpdate>(opts_.rotation));
  auto filter = std::make_unique<HessianFilter>(opts_.filter);
  filter_ = filter.get();
  steps_.push_back(std::move(filter));
  steps_.push_back(std::move(safeguard));

  // Defaults (overridable by -snes_*, -ksp_*, -pc_*).
  // rtol = 0: a residual small relative to the initial one is not equilibrium (a scrambled start has a huge one).
  // stol = 0: a step shortened by the alpha safeguard must not read as convergence.
  PetscCall(SNESSetTolerances(snes, 0.0, 0.0, 0.0, 500, PETSC_DEFAULT));
  PetscCall(SNESSetMaxLinearSolveFailures(snes, PETSC_MAX_INT));  // an unconverged CG direction is still tried
  // The line search "fails" after a residual step (it has nothing left to do); the convergence test ends the solve
  // on a real failure (NewtonSolver::convergenceTest).
  PetscCall(SNESSetMaxNonlinearStepFailures(snes, PETSC_MAX_INT));
  KSP ksp;
  PC pc;
  PetscCall(SNESGetKSP(snes, &ksp));
  PetscCall(KSPSetType(ksp, KSPCG));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCSetType(pc, PCJACOBI));
  PetscCall(KSPSetTolerances(ksp, 1e-6, PETSC_DEFAULT, PETSC_DEFAULT, 10000));
  SNESLineSearch ls;
  PetscCall(SNESGetLineSearch(snes, &ls));
  PetscCall(SNESLineSearchSetType(ls, SNESLINESEARCHBT));
  PetscCall(SNESSetConvergenceTest(snes, convergenceTest, this, nullptr));
  if (base) PetscCall(copySolverSettings(*base));
  if (floating) PetscCall(avoidMultigridWhenFloating(pc, prefix));
  if (pointBlockByRule_) PetscCall(PCSetType(pc, PCPBJACOBI));
  if (multigridByRule_) {  // smoothed aggregation as PETSc's snes ex56 sets it up for 3D elasticity
    // Two changes to ex56's set-up, measured on the static cube compression (bench/scale_out.py, 197k DoFs, 2 ranks;
    // linear-solve seconds against Jacobi's 32.6): drop-threshold 0 instead of 0.05 (faster coarsening, 29.6 -> 24.3
    // s) and one Chebyshev step per level instead of two (20.3 s: 1.5x the PCG iterations at 0.6x the cost each).
    PetscReal threshold[1] = {0.0};
    PetscCall(PCSetType(pc, PCGAMG));
    PetscCall(PCGAMGSetType(pc, PCGAMGAGG));
    PetscCall(PCGAMGSetNSmooths(pc, 1));
    PetscCall(PCGAMGSetThreshold(pc, threshold, 1));
    PetscCall(PCGAMGSetReuseInterpolation(pc, PETSC_TRUE));
    PetscCall(chooseMultigridOption(prefix, "mg_levels_ksp_max_it", "1", nullptr));
    // the hierarchy kept across Newton systems while its solves stay fast (preconditioner_reuse.hpp): a kept
    // preconditioner is still a fixed SPD one, CG stays valid. A user -snes_lag_preconditioner is PETSc's rule instead.
    PetscBool userLag = PETSC_FALSE;
    PetscCall(PetscOptionsHasName(nullptr, prefix, "-snes_lag_preconditioner", &userLag));
    if (!userLag) ctx_.preconditioner.enable(opts_.multigridReuseGrowth);
  }
  PetscCall(SNESSetFromOptions(snes));
  PetscCall(check_->setup(ctx_));
  PetscCall(configureMultigrid());
  // Hooks after SetFromOptions so a user-chosen line search type keeps them.
  PetscCall(SNESGetLineSearch(snes, &ls));
  PetscCall(SNESLineSearchSetPreCheck(ls, preCheck, this));
  PetscCall(SNESLineSearchSetPostCheck(ls, postCheck, this));
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonSolver::solve(Vec x, NewtonResult *result) {
  bool advanced;
  return solve(x, ctx_.disc->load(), result, &advanced);
}

PetscErrorCode NewtonSolver::solve(Vec x, double target, NewtonResult *result, bool *advanced) {
  KSP ksp;
  struct MemoScope {  // on for this solve, off and forgotten when it returns (error returns included)
    NewtonContext::EnergyMemo &memo;
    explicit MemoScope(NewtonContext::EnergyMemo &m) : memo(m) { memo.on = true, memo.valid = false; }
    ~MemoScope() { memo.on = memo.valid = false; }
  } memoScope(ctx_.energyMemo);
  PetscFunctionBeginUser;
  NewtonResult &cur = ctx_.result;
  cur = NewtonResult{};
  havePending_ = false;
  ctx_.iterationOffset = 0;
  *advanced = true;
  for (auto &step : steps_) PetscCall(step->beginSolve(ctx_));
  PetscCall(SNESGetKSP(ctx_.snes, &ksp));
  PetscCall(KSPGetTotalIterations(ksp, &kspBefore_));
  bool converged = false;
  if (target != ctx_.disc->load()) {
    if (opts_.lift != LiftMode::Never) PetscCall(liftIncrement(x, target, advanced, &converged));
    else *advanced = false;
    if (!*advanced) {  // nothing moved: the caller moves the supports alone (the old path)
      PetscCall(finishResult(false, result));
      PetscFunctionReturn(0);
    }
  }
  if (!converged) PetscCall(SNESSolve(ctx_.snes, nullptr, x));
  PetscCall(finishResult(!converged, result));
  if (converged) {  // by the lifted update's combined step: SNES did not run (its viewer does, as after a solve)
    PetscCall(SNESViewFromOptions(ctx_.snes, nullptr, "-snes_view"));
    Vec g;
    LocalVec xl(ctx_.disc->dm()), gl(ctx_.disc->dm());
    PetscCall(xl.fromGlobal(x, ctx_.disc));
    PetscCall(gl.zeros());
    PetscCall(VecDuplicate(ctx_.work, &g));
    PetscCall(gradientAt(xl.get(), gl.get(), g));
    PetscCall(VecNorm(g, NORM_2, &cur.residualNorm));
    PetscCall(VecDestroy(&g));
    *result = cur;
  }
  PetscFunctionReturn(0);
}

// The solve's counts and outcome: the Krylov iterations of every linear solve since it began (SNES keeps a stale
// count when it converges at iteration 0), the residual after the final correction (SNES keeps the norm from before
// it), the reason, a pending line search's record.
PetscErrorCode NewtonSolver::finishResult(bool snesRan, NewtonResult *result) {
  KSP ksp;
  PetscInt kspAfter;
  PetscFunctionBeginUser;
  NewtonResult &cur = ctx_.result;
  PetscCall(SNESGetKSP(ctx_.snes, &ksp));
  PetscCall(KSPGetTotalIterations(ksp, &kspAfter));
  cur.linearIterations = kspAfter - kspBefore_;
  cur.newtonIterations = std::max(cur.newtonIterations, ctx_.iterationOffset);
  if (snesRan) {
    Vec g;
    PetscCall(SNESGetFunction(ctx_.snes, &g, nullptr, nullptr));
    PetscCall(VecNorm(g, NORM_2, &cur.residualNorm));
    PetscCall(SNESGetConvergedReason(ctx_.snes, &cur.reason));
  }
  if (cur.reason <= 0) cur.convergence = Convergence::None;
  if (havePending_) {  // the last line search failed: keep its record
    cur.history.push_back(pending_.record);
    havePending_ = false;
  }
  if (!cur.history.empty()) cur.history.front().firstOfSolve = true;
  *result = cur;
  PetscFunctionReturn(0);
}

}  // namespace aries::solver
