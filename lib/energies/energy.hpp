// Energy density Psi(F) of a material at one element: value, PK1 (flattened gradient) and Hessian, plus the PSD
// projection used by projected Newton. The material must have passed finalizeMaterial() for this element shape.
#pragma once

#include "energies/arap_svd.hpp"
#include "energies/bw.hpp"
#include "energies/bw46.hpp"
#include "energies/fiber.hpp"
#include "energies/iarap_lin.hpp"
#include "energies/isotropic_arap_tet.hpp"
#include "energies/kim_aa.hpp"
#include "energies/shape_target.hpp"
#include "energies/volume_term.hpp"
#include "energies/weighted_arap.hpp"
#include "kernels/psd_projection.hpp"

#include <utility>

namespace aries::energies {

template <int C>
inline const Mat<C, C> &materialWeight(const Material &m) {
  if constexpr (C == 3)
    return m.weight3;
  else
    return m.weight2;
}

// How projected Newton filters an element's F-space Hessian (Newton options -psd_projection, -psd_eigensystem):
// the eigenvalue filter and whether an energy's closed-form eigensystem is used where it has one (isotropic ARAP on
// tetrahedra outside the singularity fix's band; everything else: the numeric 9x9 / 6x6 / 4x4 eigensolve).
struct HessianFilter {
  kernels::EigenFilter filter = kernels::EigenFilter::Clamp;
  bool analytic = true;
};

// `filter` (optional, with Order::Hessian): the Hessian is returned eigenvalue-filtered (evaluateFilteredEnergy).
template <int R, int C>
inline kernels::Derivs<R * C> evaluateEnergy(const Material &m, const CellData<C> &cell, const Mat<R, C> &F,
                                             kernels::Order order = kernels::Order::Hessian,
                                             const HessianFilter *filter = nullptr) {
  constexpr int N = R * C;
  constexpr bool square = (R == C);
  using kernels::Derivs;
  const bool filtered = filter && kernels::wants(order, kernels::Order::Hessian);
  auto numericFilter = [&](Derivs<N> &&d) -> Derivs<N> {
    if (filtered) d.hess = kernels::filterEigenvalues<N>(d.hess, filter->filter);
    return std::move(d);
  };

  // Energies that need no root function.
  if (m.kind == EnergyKind::Bw) return numericFilter(baraffWitkin<R, C>(F, cell.a, cell.b, m.mu1, m.mu2, order));
  if (m.kind == EnergyKind::ArapSvd) {
    Derivs<N> out = arapSvdShear<R, C>(F, m.mu, order);
    if constexpr (square)
      if (m.lambda != 0.0) out += volumeTerm<N>(kernels::invariantJ(F, order), m.lambda, 1.0, order);
    return numericFilter(std::move(out));
  }

  // Tets with an isotropic weight: fused evaluation wherever the singularity fix is inactive (isotropic_arap_tet.hpp).
  if constexpr (R == 3 && C == 3) {
    const bool isoIarap = m.kind == EnergyKind::Iarap && kernels::isIsotropic<3>(m.weight3);
    if (isoIarap || m.kind == EnergyKind::IarapLin) {
      // The closed-form filtered Hessian needs only R (first derivatives of the root).
      const bool chainRuleHessian = kernels::wants(order, kernels::Order::Hessian) && !(filtered && filter->analytic);
      const auto rd = kernels::rootDerivatives(F, chainRuleHessian ? 2 : 1);
      if (m.kind == EnergyKind::IarapLin || stretchFixInactive(m.singularity, rd.root.alpha)) {
        const double w = m.kind == EnergyKind::IarapLin ? m.mu : m.weight3(0, 0);
        if (filtered && filter->analytic)
          return isotropicArapTet(F, rd, w, 2.0 * w, 3.0 * w, m.lambda, 1.0, order, &filter->filter);
        return numericFilter(isotropicArapTet(F, rd, w, 2.0 * w, 3.0 * w, m.lambda, 1.0, order));
      }
    }
  }

  const auto ctx = kernels::makeRootContext<R, C>(F, order);
  const StretchTerms<R, C> terms(ctx, m.singularity);
  Derivs<N> out;
  auto addVolume = [&](double J0) {
    if constexpr (square)
      if (m.lambda != 0.0) out += volumeTerm<N>(jacobianOf<R>(ctx), m.lambda, J0, order);
  };
  switch (m.kind) {
    case EnergyKind::Alx:
      out = weightedArap<R, C>(ctx, terms, 0.5 * m.mu * kernels::fiberTensor<C>(cell.a));
      break;
    case EnergyKind::Iarap:
    case EnergyKind::Ortho:
    case EnergyKind::Aniso:
      out = weightedArap<R, C>(ctx, terms, materialWeight<C>(m));
      addVolume(1.0);
      break;
    case EnergyKind::IarapLin:
      out = iarapLinShear<R, C>(ctx, m.mu);
      addVolume(1.0);
      break;
    case EnergyKind::Fiber:
      out = weightedArap<R, C>(ctx, terms, materialWeight<C>(m));
      out += fiberStiffening<R, C>(terms, cell.a, m.gamma, order);
      addVolume(1.0);
      break;
    case EnergyKind::KimAA: {
      // Kim's term "in the same manner" as Eq. 39: one Psi_AA per basis direction, coefficient 2 mu each.
      for (int k = 0; k < C; ++k) {
        const Vec<C> u = m.basis.row(k).template head<C>().transpose();
        out += kimAATerm<R, C>(ctx, u, 2.0 * m.mu);
      }
      addVolume(1.0);
      break;
    }
    case EnergyKind::Bw46:
      out = iarapLinShear<R, C>(ctx, 0.5 * m.mu1);
      break;
    case EnergyKind::Bw461:
      out = decoupledCloth<R, C>(terms, cell.a, cell.b, m.mu1, m.mu2, 0.0, order);
      break;
    case EnergyKind::Bw46s:
      out = decoupledCloth<R, C>(terms, cell.a, cell.b, m.mu1, m.mu2, cell.a.dot(cell.b), order);
      break;
    case EnergyKind::ShapeTarget:
      out = shapeTargetShear<R, C>(ctx, terms, cell.target, m.mu);
      addVolume(cell.target.determinant());
      break;
    case EnergyKind::Caricature: {
      out = weightedArap<R, C>(ctx, terms, materialWeight<C>(m));
      // Eq. 66 in the iarap's units (iarap = mu Psi_iARAP): mu (Psi_iARAP + beta c I4(n)), so beta is
      // dimensionless and the element targets the stretch 1 - beta c / 2 along n (Eq. 65 with 2 (1 - lambda_1) = beta c).
      out += terms(kernels::fiberTensor<C>(cell.a)).scale(m.mu * m.beta * cell.curvature);
      addVolume(1.0);
      break;
    }
    case EnergyKind::Bw:
    case EnergyKind::ArapSvd:
      break;  // handled above
  }
  out += terms.barrier();
  return numericFilter(std::move(out));
}

// Value, PK1 and the eigenvalue-filtered Hessian (projected Newton): through the energy's closed-form eigensystem
// where it has one and filter.analytic is set, else by the numeric eigensolve of psd_projection.hpp.
template <int R, int C>
inline kernels::Derivs<R * C> evaluateFilteredEnergy(const Material &m, const CellData<C> &cell, const Mat<R, C> &F,
                                                     const HessianFilter &filter) {
  return evaluateEnergy<R, C>(m, cell, F, kernels::Order::Hessian, &filter);
}

// The singularity measure alpha at F (the line-search safeguard's quantity).
template <int R, int C>
inline double elementAlpha(const Mat<R, C> &F) {
  return kernels::rootValue(F).alpha;
}

}  // namespace aries::energies
