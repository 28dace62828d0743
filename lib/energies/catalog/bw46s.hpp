// bw46s: mu1/2 [(I4(a) - 1)^2 + (I4(b) - 1)^2] + mu2 (I6(a,b) - a.b)^2 (Eq. 53), cloth with non-orthogonal fibers.
#pragma once

#include "energies/bw46.hpp"
#include "energies/descriptor.hpp"

namespace aries::energies {

struct Bw46sEnergy : EnergyDefaults {
  static constexpr const char *name = "bw46s";
  static constexpr const char *summary = "mu1/2 [(I4(a) - 1)^2 + (I4(b) - 1)^2] + mu2 (I6(a,b) - a.b)^2 (Eq. 53)";
  static constexpr bool tet = false, planar = false, cloth = true, stretch = true, fibers = true;
  template <int R, int C>
  static kernels::Derivs<R * C> evaluate(const EnergyInput<R, C> &in) {
    return rootEnergy(in, [&](const auto &, const auto &terms, auto &out) {
      out = decoupledCloth<R, C>(terms, in.cell.a, in.cell.b, in.m.mu1, in.m.mu2, in.cell.a.dot(in.cell.b), in.order);
    });
  }
};

}  // namespace aries::energies
