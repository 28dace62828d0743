// Every energy of the registry on cloth elements (3x2 F), compiled once (energies/evaluate_registered.hpp).
#include "energies/evaluate_registered.hpp"

namespace aries::energies {
template kernels::Derivs<6> evaluateRegisteredEnergy<3, 2>(const EnergyInput<3, 2> &);
}  // namespace aries::energies
