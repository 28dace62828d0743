// kim_aa: Kim 2019's Psi_AA (Eq. 9) "in the same manner" as Eq. 39, one term per basis direction with coefficient
// 2 mu, + lambda/2 (J - 1)^2; the baseline with its known flaws.
#pragma once

#include "energies/descriptor.hpp"
#include "energies/kim_aa.hpp"

namespace aries::energies {

struct KimAAEnergy : EnergyDefaults {
  static constexpr const char *name = "kim_aa";
  static constexpr const char *summary =
      "Kim 2019 Psi_AA per basis direction (coefficient 2 mu) + volume term; baseline with its known flaws";
  static constexpr bool basis = true, volume = true;
  template <int R, int C>
  static kernels::Derivs<R * C> evaluate(const EnergyInput<R, C> &in) {
    return rootEnergy(in, [&](const auto &ctx, const auto &, auto &out) {
      for (int k = 0; k < C; ++k) {
        const Vec<C> u = in.m.basis.row(k).template head<C>().transpose();
        out += kimAATerm<R, C>(ctx, u, 2.0 * in.m.mu);
      }
      addVolume(in, ctx, 1.0, out);
    });
  }
};

}  // namespace aries::energies
