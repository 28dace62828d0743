// ortho: sum_k mu_k |(F - R) u_k|^2 + lambda/2 (J - 1)^2 over an orthonormal basis u_k (-fiber, -fiber2, their cross
// product), one shear modulus per direction (-ortho_mu); orthotropic layering (paper Sec. 5.1).
#pragma once

#include "energies/descriptor.hpp"

namespace aries::energies {

struct OrthoEnergy : EnergyDefaults {
  static constexpr const char *name = "ortho";
  static constexpr const char *summary = "sum_k mu_k |(F - R) u_k|^2 + volume term";
  static constexpr bool stretch = true, basis = true, volume = true, shear = false;
  static constexpr std::array<ParamSpec, 1> params{{
      {"-ortho_mu", "shear modulus per basis direction (-fiber, -fiber2, cross product), one value each",
       ParamKind::PerAxis, nullptr, nullptr, true},
  }};
  static std::string finalize(Material &m, int dim) {
    for (int k = 0; k < dim; ++k) {
      if (!std::isfinite(m.basisCoeffs[k]) || m.basisCoeffs[k] < 0.0)
        return "energy 'ortho' needs -ortho_mu with one value >= 0 per direction";
      addWeightDirection(m, m.basis.row(k).transpose(), m.basisCoeffs[k]);
    }
    return {};
  }
  template <int R, int C>
  static kernels::Derivs<R * C> evaluate(const EnergyInput<R, C> &in) {
    return layeredArap(in);
  }
};

}  // namespace aries::energies
