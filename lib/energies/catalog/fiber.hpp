// fiber: iarap + gamma/2 (I4(a) - 1)^2, a stiffened fiber direction (paper Sec. 6, the octopus).
#pragma once

#include "energies/descriptor.hpp"
#include "energies/fiber.hpp"
#include "energies/weighted_arap.hpp"

namespace aries::energies {

struct FiberEnergy : EnergyDefaults {
  static constexpr const char *name = "fiber";
  static constexpr const char *summary = "iarap + gamma/2 (I4(a) - 1)^2";
  static constexpr bool stretch = true, fibers = true, volume = true;
  static constexpr std::array<ParamSpec, 1> params{{
      {"-gamma", "fiber stiffness (>= 0)", ParamKind::Real, &Material::gamma, nullptr, true},
  }};
  static std::string finalize(Material &m, int dim) {
    if (!std::isfinite(m.gamma) || m.gamma < 0.0) return "energy 'fiber' needs -gamma >= 0 (fiber stiffness)";
    return isotropicWeight(m, dim);
  }
  template <int R, int C>
  static kernels::Derivs<R * C> evaluate(const EnergyInput<R, C> &in) {
    return rootEnergy(in, [&](const auto &ctx, const auto &terms, auto &out) {
      out = weightedArap<R, C>(ctx, terms, materialWeight<C>(in.m));
      out += fiberStiffening<R, C>(terms, in.cell.a, in.m.gamma, in.order);
      addVolume(in, ctx, 1.0, out);
    });
  }
};

}  // namespace aries::energies
