// iarap: mu |F - R|^2 + lambda/2 (J - 1)^2 as the sum of direction terms over an orthonormal basis (Eq. 39); small
// strain = linear elasticity with (E, nu). Tets with an isotropic weight take the fused closed form
// (isotropic_arap_tet.hpp) wherever the singularity fix is inactive, with the closed-form eigensystem for
// projected Newton.
#pragma once

#include "energies/descriptor.hpp"
#include "energies/isotropic_arap_tet.hpp"

namespace aries::energies {

// The fused tet evaluation with weight w (iarap_lin's value at every F, iarap's outside the fix's band).
// One named result returned (no copy of its 91 numbers); filtered by the closed-form eigensystem where the filter is
// analytic, else by the numeric one (EnergyInput::filterNumerically).
template <int R, int C, kernels::IfShape<R, C, 3, 3> = 0>
inline kernels::Derivs<9> fusedIsotropicArapTet(const EnergyInput<R, C> &in, const kernels::RootDerivatives<3> &rd,
                                                double w) {
  const bool analytic = in.filtered() && in.filter->analytic;
  kernels::Derivs<9> out = isotropicArapTet(in.F, rd, w, 2.0 * w, 3.0 * w, in.m.lambda, 1.0, in.order,
                                            analytic ? &in.filter->filter : nullptr);
  if (!analytic) in.filterNumerically(out);
  return out;
}
// The root's derivatives the fused evaluation needs: the closed-form filtered Hessian needs only R.
template <int R, int C, kernels::IfShape<R, C, 3, 3> = 0>
inline kernels::RootDerivatives<3> fusedRootDerivatives(const EnergyInput<R, C> &in) {
  const bool chainRuleHessian =
      kernels::wants(in.order, kernels::Order::Hessian) && !(in.filtered() && in.filter->analytic);
  return kernels::rootDerivatives(in.F, chainRuleHessian ? 2 : 1);
}
// The fused evaluation with weight w where the singularity fix is inactive, else general() (the caller's generic
// direction terms, which handle the fix's band). Both are returned as prvalues, so the 91 numbers of a Derivs<9> are
// written once (a std::optional in between cost two copies of them per point, a measurable share of an assembly).
template <class General>
inline kernels::Derivs<9> fusedOutsideFixBand(const EnergyInput<3, 3> &in, double w, General &&general) {
  const auto rd = fusedRootDerivatives(in);
  if (stretchFixInactive(in.m.singularity, in.F, rd.root.alpha)) return fusedIsotropicArapTet(in, rd, w);
  return general();
}

struct IarapEnergy : EnergyDefaults {
  static constexpr const char *name = "iarap";
  static constexpr const char *summary =
      "mu |F - R|^2 + lambda/2 (J - 1)^2 as the sum of direction terms (Eq. 39); small strain = linear elasticity "
      "(E, nu)";
  static constexpr bool stretch = true, volume = true, isotropic = true;
  static std::string finalize(Material &m, int dim) { return isotropicWeight(m, dim); }
  template <int R, int C>
  static kernels::Derivs<R * C> evaluate(const EnergyInput<R, C> &in) {
    if constexpr (R == 3 && C == 3) {
      if (kernels::isIsotropic<3>(in.m.weight3))
        return fusedOutsideFixBand(in, in.m.weight3(0, 0), [&] { return layeredArap(in); });
    }
    return layeredArap(in);
  }
};

}  // namespace aries::energies
