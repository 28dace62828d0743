// Projected Newton on the total potential with PETSc SNES (newtonls), KSP CG + Jacobi by default:
//  * the energy is the SNES objective (line searches backtrack on it), its gradient the residual, the assembled
//    PSD-projected Hessian the Jacobian (DMSNES local callbacks; Dirichlet values filled by the boundary callback);
//  * the alpha safeguard (paper Sec. 4.2) as line-search pre/post checks: no accepted step makes an element's alpha
//    drop below -alpha_min (elements already below it are not constrained); the step is halved until it holds. The
//    pre-check covers bt/basic/l2/cp, the post-check catches line searches that extrapolate (lambda > 1);
//  * convergence when the inf-norm of the full Newton step is below -newton_tol * L (* dt for dynamics), L the
//    rest bounding-box diagonal (paper Sec. 6), or on PETSc's usual criteria.
//  * the rigid-body modes of the rest shape as the Jacobian's near-nullspace (-near_nullspace rigid|none), for GAMG.
// Every default is a PETSc option and can be overridden (-snes_*, -ksp_*, -pc_*, -snes_linesearch_*).
#pragma once

#include "fem/discretization.hpp"

#include <petscsnes.h>

namespace aries::solver {

struct NewtonResult {
  PetscInt newtonIterations = 0;
  PetscInt linearIterations = 0;
  PetscInt safeguardHalvings = 0;
  SNESConvergedReason reason = SNES_CONVERGED_ITERATING;
  bool stepCriterion = false;  // converged by the Newton-step criterion (reported as "newton_step")
  PetscInt barrierFallbackCells = 0;  // cells evaluated with the mollifier in barrier mode (alpha ~ 0)
  PetscReal residualNorm = 0.0;       // |gradient of the potential| over the free dofs at the last iterate
  bool converged() const { return reason > 0; }
};

class NewtonSolver {
 public:
  ~NewtonSolver();
  // Reads -newton_tol and -alpha_min; `dynamic` selects the dt-scaled tolerance.
  PetscErrorCode setup(fem::Discretization &disc, bool dynamic, double dt);
  PetscErrorCode solve(Vec x, NewtonResult *result);  // x: initial guess in, solution out (global, free dofs)

  // alpha check of a state against reference alphas (the state before the step): true unless a cell whose reference
  // alpha is >= alphaMin ends below alphaMin (or any alpha is NaN).
  PetscErrorCode alphaAcceptable(Vec xGlobal, const std::vector<double> &reference, bool *ok);
  PetscErrorCode alphasAt(Vec xGlobal, std::vector<double> *alpha);
  double alphaMin() const { return alphaMin_; }
  double stepTolerance() const { return stepTol_; }
  SNES snes() const { return snes_; }
  PetscInt totalHalvings() const { return halvingsTotal_; }

 private:
  PetscErrorCode attachNearNullSpace();
  PetscErrorCode configureMultigrid();
  static PetscErrorCode objectiveCallback(SNES, Vec, PetscReal *, void *);
  static PetscErrorCode boundaryLocal(DM, Vec, void *);
  static PetscErrorCode functionLocal(DM, Vec, Vec, void *);
  static PetscErrorCode jacobianLocal(DM, Vec, Mat, Mat, void *);
  static PetscErrorCode preCheck(SNESLineSearch, Vec, Vec, PetscBool *, void *);
  static PetscErrorCode postCheck(SNESLineSearch, Vec, Vec, Vec, PetscBool *, PetscBool *, void *);
  static PetscErrorCode convergenceTest(SNES, PetscInt, PetscReal, PetscReal, PetscReal, SNESConvergedReason *,
                                        void *);

  fem::Discretization *disc_ = nullptr;
  SNES snes_ = nullptr;
  Mat J_ = nullptr;
  Vec work_ = nullptr;
  double alphaMin_ = 1e-6;
  double stepTol_ = 0.0;
  double lastStepInf_ = -1.0;
  bool stepCriterion_ = false;
  std::vector<double> alphaRef_;
  PetscInt halvings_ = 0, halvingsTotal_ = 0;
  PetscLogStage assemblyStage_ = -1;
};

}  // namespace aries::solver
