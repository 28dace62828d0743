// bw46: mu1/2 (I2 - 2 I1 + 2), the isotropic cloth energy (Eq. 49) and the cloth default.
#pragma once

#include "energies/descriptor.hpp"
#include "energies/iarap_lin.hpp"

namespace aries::energies {

struct Bw46Energy : EnergyDefaults {
  static constexpr const char *name = "bw46";
  static constexpr const char *summary = "mu1/2 (I2 - 2 I1 + 2) (Eq. 49)";
  static constexpr bool tet = false, planar = false, cloth = true, mu2 = false;
  template <int R, int C>
  static kernels::Derivs<R * C> evaluate(const EnergyInput<R, C> &in) {
    return rootEnergy(in, [&](const auto &ctx, const auto &, auto &out) { out = iarapLinShear<R, C>(ctx, 0.5 * in.m.mu1); });
  }
};

}  // namespace aries::energies
