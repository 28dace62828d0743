// shape_target: mu/2 |F - R S_t|^2 + lambda/2 (J - det S_t)^2 in the form of Eq. 65 (note mu/2, Eq. 54's scale),
// with a symmetric target S_t per element (-target, or from -activation / -target_file in the solver).
// On tets a cell at its rest target (S_t = I: every cell before and after a keyframed performance, most cells of a
// partial activation) has mu/2 |F - R|^2 + lambda/2 (J - 1)^2, iarap_lin with mu/2: it takes iarap_lin's fused closed
// form and closed-form eigensystem (Smith et al. 2019, kernels/isotropic_eigensystem.hpp) instead of the generic
// terms and the numeric 9x9 eigensolve. The same energy: the same value and PK1, the filtered Hessian to round-off
// (test_isotropic_eigensystem.cpp).
#pragma once

#include "energies/catalog/iarap.hpp"
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
    if constexpr (R == 3 && C == 3) {
      if (in.cell.target == Mat<3, 3>::Identity())  // the tensor term D = I - S_t vanishes (Eq. 65): iarap_lin, mu/2
        return fusedOutsideFixBand(in, 0.5 * in.m.mu, [&] { return general(in); });
    }
    return general(in);
  }

 private:
  template <int R, int C>
  static kernels::Derivs<R * C> general(const EnergyInput<R, C> &in) {
    return rootEnergy(in, [&](const auto &ctx, const auto &terms, auto &out) {
      out = shapeTargetShear<R, C>(ctx, terms, in.cell.target, in.m.mu);
      addVolume(in, ctx, in.cell.target.determinant(), out);
    });
  }
};

}  // namespace aries::energies
