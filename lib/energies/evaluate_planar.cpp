// Every energy of the registry on planar elements (2x2 F), compiled once (energies/evaluate_registered.hpp).
#include "energies/evaluate_registered.hpp"

namespace aries::energies {
template kernels::Derivs<4> evaluateRegisteredEnergy<2, 2>(const EnergyInput<2, 2> &);
}  // namespace aries::energies
