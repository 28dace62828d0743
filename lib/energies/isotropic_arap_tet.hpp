// Fused evaluation of the isotropic ARAP family on tetrahedra:
//   Psi = a I_C - b f + c + lambda/2 (J - J0)^2          (iarap / iarap_lin: a = mu, b = 2 mu, c = 3 mu, J0 = 1)
// with PK1 2a F - b R + lambda (J - J0) cof F and Hessian
//   (2a - 2b f_1) Id - b f_2 d2II_C - (b f_J - lambda (J - J0)) d2J + G D G^T,  G = [2F, 4FC, cof F],
//   D = -b [f_kl] + lambda e_J e_J^T,
// i.e. the same chain rule as the general path (Eqs. 12, 19, 39-42) written into one 9x9 matrix without
// intermediate invariant Hessians. Used where the singularity fix is inactive (the general path handles the
// mollifier band and the barrier support, and stays the reference it is tested against).
#pragma once

#include "energies/material.hpp"
#include "kernels/isotropic_eigensystem.hpp"

namespace aries::energies {

// With `filter`, the Hessian is the eigenvalue-filtered one, built from the closed-form eigensystem of this
// Psi(I1, I2, I3) (isotropic_eigensystem.hpp: Psi_1 = -b, Psi_2 = a, Psi_3 = lambda (J - J0), Psi_33 = lambda) instead
// of the chain rule followed by a 9x9 eigensolve.
template <int Rows, int Cols, kernels::IfShape<Rows, Cols, 3, 3> = 0>
inline kernels::Derivs<9> isotropicArapTet(const Mat<Rows, Cols> &F, const kernels::RootDerivatives<3> &rd, double a,
                                           double b, double c, double lambda, double J0, kernels::Order order,
                                           const kernels::EigenFilter *filter = nullptr) {
  using kernels::Order;
  kernels::Derivs<9> out;
  const double J = F.determinant(), IC = F.squaredNorm(), f = rd.root.f, dJ = J - J0;
  out.value = a * IC - b * f + c + 0.5 * lambda * dJ * dJ;
  if (!kernels::wants(order, Order::Gradient)) return out;
  const Mat<3, 3> cof = kernels::cofactor(F);
  const Mat<3, 3> R = kernels::rotationFromRoot(F, rd);
  out.grad = kernels::flatten<3, 3>(Mat<3, 3>(2.0 * a * F - b * R + lambda * dJ * cof));
  if (!kernels::wants(order, Order::Hessian)) return out;
  if (filter) {
    kernels::IsotropicPsiDerivatives psi;
    psi.first << -b, a, lambda * dJ;
    psi.second(2, 2) = lambda;
    out.hess = kernels::filteredIsotropicHessian(F, R, psi, *filter);
    return out;
  }
  const Mat<3, 3> Cg = F.transpose() * F;
  out.hess.diagonal().setConstant(2.0 * a - 2.0 * b * rd.d1[0]);
  kernels::addHessianIIC<3, 3>(F, Cg, -b * rd.d1[1], out.hess);
  kernels::addHessianJ(F, lambda * dJ - b * rd.d1[2], out.hess);
  Mat<9, 3> G;
  G.col(0) = 2.0 * kernels::flatten<3, 3>(F);
  G.col(1) = 4.0 * kernels::flatten<3, 3>(Mat<3, 3>(F * Cg));
  G.col(2) = kernels::flatten<3, 3>(cof);
  Mat<3, 3> D = -b * rd.d2;
  D(2, 2) += lambda;
  const Mat<9, 3> GD = G.lazyProduct(D);
  out.hess.noalias() += GD.lazyProduct(G.transpose());
  return out;
}

// True where the mode's I4/I6 treatment equals the raw closed form at this alpha (so the fused path applies).
inline bool stretchFixInactive(const SingularityParams &sp, const Mat<3, 3> &F, double alpha) {
  switch (sp.mode) {
    case SingularityMode::None: return true;
    case SingularityMode::Mollifier:
      return kernels::aboveMollifierBand(kernels::mollifierCoordinate<3, 3>(F, alpha, sp.mollifier), sp.mollifier);
    case SingularityMode::Barrier: return alpha >= sp.barrier.eps;
  }
  return false;
}

}  // namespace aries::energies
