// 5. HessianFilter (newton_steps.hpp, -psd_projection clamp|abs|adaptive|none, -psd_eigensystem, -psd_scope,
// -psd_adaptive_tol): the eigenvalue filter of the element Hessians (kernels/psd_projection.hpp), per quadrature point
// or per whole element. Adaptive picks clamp or abs per Newton
// iteration by the trust-region ratio of the previous update (Chen et al. 2024): rho = actual / predicted decrease with
// the true quadratic model of the update taken; clamp where the model is trustworthy (|rho - 1| < -psd_adaptive_tol:
// fast local convergence), abs otherwise (robust far from equilibrium). The first iteration of a solve has no model
// to judge: abs.
#include "solver/newton_steps.hpp"

#include <cmath>

namespace aries::solver {

PetscErrorCode HessianFilter::beginSolve(NewtonContext &ctx) {
  kernels::EigenFilter initial = kernels::EigenFilter::Clamp;
  switch (opts_.mode) {
    case EigenFilterMode::Clamp: initial = kernels::EigenFilter::Clamp; break;
    case EigenFilterMode::None: initial = kernels::EigenFilter::None; break;
    case EigenFilterMode::Abs:
    case EigenFilterMode::Adaptive: initial = kernels::EigenFilter::Abs; break;
  }
  ctx.disc->setEigenFilter(initial);
  ctx.disc->setAnalyticEigensystem(opts_.analyticEigensystem);
  ctx.disc->setWholeElementFilter(opts_.wholeElement);
  return 0;
}

// The adaptive filter judges the update by its curvature: the subspace step's model knows it, else one product.
PetscErrorCode HessianFilter::shapeDirection(NewtonContext &ctx, Direction &d, Vec X, Vec Y, Vec, PetscBool *) {
  PetscFunctionBeginUser;
  if (opts_.mode != EigenFilterMode::Adaptive || d.haveCurvature) PetscFunctionReturn(0);
  std::vector<double> G;
  PetscCall(ctx.gram(X, {Y}, &G));
  d.curvature = G[0];
  d.haveCurvature = true;
  PetscFunctionReturn(0);
}

PetscErrorCode HessianFilter::finishUpdate(NewtonContext &ctx, const Direction &d, Vec xNew, double lambda) {
  PetscFunctionBeginUser;
  if (opts_.mode != EigenFilterMode::Adaptive || !d.haveCurvature) PetscFunctionReturn(0);
  PetscReal energy;
  PetscCall(ctx.energyAt(xNew, &energy, nullptr));
  const double predicted = lambda * d.slope - 0.5 * lambda * lambda * d.curvature;
  const double rho = predicted != 0.0 ? (d.energyBefore - energy) / predicted : 0.0;
  ctx.disc->setEigenFilter(std::abs(rho - 1.0) < opts_.adaptiveTol ? kernels::EigenFilter::Clamp
                                                                    : kernels::EigenFilter::Abs);
  PetscFunctionReturn(0);
}

}  // namespace aries::solver
