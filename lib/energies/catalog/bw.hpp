// bw: Baraff-Witkin in Kim 2020's form (Eq. 45), cloth: mu1/2 [(sqrt I5(a) - 1)^2 + (sqrt I5(b) - 1)^2]
// + mu2 (I7(a,b) - a.b)^2; needs no root function.
#pragma once

#include "energies/bw.hpp"
#include "energies/descriptor.hpp"

namespace aries::energies {

struct BwEnergy : EnergyDefaults {
  static constexpr const char *name = "bw";
  static constexpr const char *summary =
      "mu1/2 [(sqrt I5(a) - 1)^2 + (sqrt I5(b) - 1)^2] + mu2 (I7(a,b) - a.b)^2 (Kim 2020)";
  static constexpr bool tet = false, planar = false, cloth = true, fibers = true;
  template <int R, int C>
  static kernels::Derivs<R * C> evaluate(const EnergyInput<R, C> &in) {
    return in.finish(baraffWitkin<R, C>(in.F, in.cell.a, in.cell.b, in.m.mu1, in.m.mu2, in.order));
  }
};

}  // namespace aries::energies
