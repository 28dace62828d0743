// alx: mu/2 (I5(a) - 2 I4(a) + 1), one fiber a (Eq. 38).
#pragma once

#include "energies/descriptor.hpp"
#include "energies/weighted_arap.hpp"

namespace aries::energies {

struct AlxEnergy : EnergyDefaults {
  static constexpr const char *name = "alx";
  static constexpr const char *summary = "mu/2 (I5(a) - 2 I4(a) + 1) (Eq. 38)";
  static constexpr bool stretch = true, fibers = true;
  template <int R, int C>
  static kernels::Derivs<R * C> evaluate(const EnergyInput<R, C> &in) {
    return rootEnergy(in, [&](const auto &ctx, const auto &terms, auto &out) {
      out = weightedArap<R, C>(ctx, terms, 0.5 * in.m.mu * kernels::fiberTensor<C>(in.cell.a));
    });
  }
};

}  // namespace aries::energies
