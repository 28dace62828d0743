// shape_target: mu/2 |F - R S_t|^2 + lambda/2 (J - det S_t)^2 in the form of Eq. 65 (note mu/2, Eq. 54's scale),
// with a symmetric target S_t per element (-target, or from -activation / -target_file in the solver).
#pragma once

#include "energies/descriptor.hpp"
#include "energies/shape_target.hpp"

namespace aries::energies {

struct ShapeTargetEnergy : EnergyDefaults {
  static constexpr const char *name = "shape_target";
  static constexpr const char *summary = "mu/2 |F - R S_t|^2 + lambda/2 (J - det S_t)^2 in the form of Eq. 65";
  static constexpr bool stretch = true, volume = true;
  static constexpr CellField cellField = CellField::ShapeTargets;
  static constexpr std::array<ParamSpec, 1> params{{
      {"-target", "uniform symmetric shape target S_t, d x d numbers row by row (default: identity)",
       ParamKind::SymmetricMatrix},
  }};
  template <int R, int C>
  static kernels::Derivs<R * C> evaluate(const EnergyInput<R, C> &in) {
    return rootEnergy(in, [&](const auto &ctx, const auto &terms, auto &out) {
      out = shapeTargetShear<R, C>(ctx, terms, in.cell.target, in.m.mu);
      addVolume(in, ctx, in.cell.target.determinant(), out);
    });
  }
};

}  // namespace aries::energies
