// aniso: sum_k c_k |(F - R) d_k|^2 + lambda/2 (J - 1)^2 for up to 8 unit directions d_k of any orientation
// (-aniso_dirs) with coefficients c_k (-aniso_mu); general anisotropic layering (paper Sec. 5.1).
#pragma once

#include "energies/descriptor.hpp"

namespace aries::energies {

struct AnisoEnergy : EnergyDefaults {
  static constexpr const char *name = "aniso";
  static constexpr const char *summary = "sum_k c_k |(F - R) d_k|^2 + volume term";
  static constexpr bool stretch = true, volume = true, shear = false;
  static constexpr std::array<ParamSpec, 1> params{{
      {"-aniso_dirs", "1 to 8 directions d_k (d numbers each; normalized) and one coefficient c_k per direction",
       ParamKind::Directions, nullptr, nullptr, true, "-aniso_mu"},
  }};
  static std::string finalize(Material &m, int dim) {
    if (m.numDirections < 1 || m.numDirections > kMaxDirections)
      return "energy 'aniso' needs -aniso_dirs with 1 to 8 directions and -aniso_mu with one coefficient each";
    for (int k = 0; k < m.numDirections; ++k) {
      const Eigen::Vector3d d = m.directions[k];
      if (dim == 2 && std::abs(d[2]) > 1e-12) return "planar elements need -aniso_dirs in the xy plane (z = 0)";
      if (!(d.norm() > 0.0) || !std::isfinite(d.norm())) return "-aniso_dirs contains a zero-length or non-finite direction";
      if (!std::isfinite(m.directionCoeffs[k]) || m.directionCoeffs[k] < 0.0) return "-aniso_mu coefficients must be >= 0";
      addWeightDirection(m, d.normalized(), m.directionCoeffs[k]);
    }
    return {};
  }
  template <int R, int C>
  static kernels::Derivs<R * C> evaluate(const EnergyInput<R, C> &in) {
    return layeredArap(in);
  }
};

}  // namespace aries::energies
