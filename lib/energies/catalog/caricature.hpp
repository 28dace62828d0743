// caricature: iarap + mu beta c I4(n) (Eq. 66 in the iarap's units: iarap = mu Psi_iARAP, so beta is dimensionless
// and an element targets the stretch 1 - beta c / 2 along n, Eq. 65 with 2 (1 - lambda_1) = beta c); c and n per
// element (the solver computes them from the mesh surface).
#pragma once

#include "energies/descriptor.hpp"
#include "energies/weighted_arap.hpp"

namespace aries::energies {

struct CaricatureEnergy : EnergyDefaults {
  static constexpr const char *name = "caricature";
  static constexpr const char *summary = "iarap + beta c I4(n) (Eq. 66)";
  static constexpr bool planar = false, stretch = true, fibers = true, volume = true;
  static constexpr CellField cellField = CellField::SurfaceCurvature;
  static constexpr std::array<ParamSpec, 2> params{{
      {"-beta", "curvature exaggeration (dimensionless)", ParamKind::Real, &Material::beta, nullptr, true},
      {"-curvature", "curvature ratio c of the element (aries-matpoint; the solver takes it from the surface)",
       ParamKind::CellReal, nullptr, &UniformCellData::curvature},
  }};
  static std::string finalize(Material &m, int dim) {
    if (!std::isfinite(m.beta)) return "energy 'caricature' needs a finite -beta";
    return isotropicWeight(m, dim);
  }
  template <int R, int C>
  static kernels::Derivs<R * C> evaluate(const EnergyInput<R, C> &in) {
    return rootEnergy(in, [&](const auto &ctx, const auto &terms, auto &out) {
      out = weightedArap<R, C>(ctx, terms, materialWeight<C>(in.m));
      out += terms(kernels::fiberTensor<C>(in.cell.a)).scale(in.m.mu * in.m.beta * in.cell.curvature);
      addVolume(in, ctx, 1.0, out);
    });
  }
};

}  // namespace aries::energies
