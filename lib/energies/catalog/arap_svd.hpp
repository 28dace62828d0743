// arap_svd: iarap's shear term with R from a signed SVD (the reference and the baseline), + lambda/2 (J - 1)^2.
#pragma once

#include "energies/arap_svd.hpp"
#include "energies/descriptor.hpp"

namespace aries::energies {

struct ArapSvdEnergy : EnergyDefaults {
  static constexpr const char *name = "arap_svd";
  static constexpr const char *summary = "the same with R from an SVD (reference, baseline)";
  static constexpr bool volume = true;
  template <int R, int C>
  static kernels::Derivs<R * C> evaluate(const EnergyInput<R, C> &in) {
    kernels::Derivs<R * C> out = arapSvdShear<R, C>(in.F, in.m.mu, in.order);
    if constexpr (R == C)
      if (in.m.lambda != 0.0) out += volumeTerm<R * C>(kernels::invariantJ(in.F, in.order), in.m.lambda, 1.0, in.order);
    return in.finish(std::move(out));
  }
};

}  // namespace aries::energies
