// The registry's evaluation for one element shape, compiled once per shape (evaluate_tet.cpp, evaluate_planar.cpp,
// evaluate_cloth.cpp hold the explicit instantiations; energy.hpp declares them extern). Include only there: a
// translation unit that sees this definition compiles every energy's kernels again.
#pragma once

#include "energies/energy.hpp"

namespace aries::energies {

template <int R, int C>
kernels::Derivs<R * C> evaluateRegisteredEnergy(const EnergyInput<R, C> &in) {
  return evaluateRegistered<R, C>(in);
}

}  // namespace aries::energies
