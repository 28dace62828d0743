// Every energy of the registry on tet elements (3x3 F), compiled once (energies/evaluate_registered.hpp).
#include "energies/evaluate_registered.hpp"

namespace aries::energies {
template kernels::Derivs<9> evaluateRegisteredEnergy<3, 3>(const EnergyInput<3, 3> &);
}  // namespace aries::energies
