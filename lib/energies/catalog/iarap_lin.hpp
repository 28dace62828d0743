// iarap_lin: mu (I2 - 2 I1 + d) + lambda/2 (J - 1)^2 (Lin et al. 2022, Eq. 40): no singularity fix, so tets always
// take the fused closed form of iarap.hpp.
#pragma once

#include "energies/catalog/iarap.hpp"
#include "energies/iarap_lin.hpp"

namespace aries::energies {

struct IarapLinEnergy : EnergyDefaults {
  static constexpr const char *name = "iarap_lin";
  static constexpr const char *summary = "mu (I2 - 2 I1 + d) + lambda/2 (J - 1)^2 (Lin 2022, Eq. 40)";
  static constexpr bool volume = true;
  template <int R, int C>
  static kernels::Derivs<R * C> evaluate(const EnergyInput<R, C> &in) {
    if constexpr (R == 3 && C == 3) return fusedIsotropicArapTet(in, fusedRootDerivatives(in), in.m.mu);
    return rootEnergy(in, [&](const auto &ctx, const auto &, auto &out) {
      out = iarapLinShear<R, C>(ctx, in.m.mu);
      addVolume(in, ctx, 1.0, out);
    });
  }
};

}  // namespace aries::energies
