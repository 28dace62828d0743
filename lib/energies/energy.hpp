// Energy density Psi(F) of a material at one element: value, PK1 (flattened gradient) and Hessian, plus the PSD
// projection used by projected Newton. The material must have passed finalizeMaterial() for this element shape.
#pragma once

#include "energies/registry.hpp"

namespace aries::energies {

// The registry's dispatch, compiled once per element shape (evaluate_tet.cpp, evaluate_planar.cpp,
// evaluate_cloth.cpp): the translation units that evaluate energies (assembly, diagnostics, the tests) do not each
// compile every energy's kernels.
template <int R, int C>
kernels::Derivs<R * C> evaluateRegisteredEnergy(const EnergyInput<R, C> &in);
extern template kernels::Derivs<9> evaluateRegisteredEnergy<3, 3>(const EnergyInput<3, 3> &);
extern template kernels::Derivs<4> evaluateRegisteredEnergy<2, 2>(const EnergyInput<2, 2> &);
extern template kernels::Derivs<6> evaluateRegisteredEnergy<3, 2>(const EnergyInput<3, 2> &);

// `filter` (optional, with Order::Hessian): the Hessian is returned eigenvalue-filtered (evaluateFilteredEnergy).
template <int R, int C>
inline kernels::Derivs<R * C> evaluateEnergy(const Material &m, const CellData<C> &cell, const Mat<R, C> &F,
                                             kernels::Order order = kernels::Order::Hessian,
                                             const HessianFilter *filter = nullptr) {
  return evaluateRegisteredEnergy<R, C>(EnergyInput<R, C>{m, cell, F, order, filter});
}

// Value, PK1 and the eigenvalue-filtered Hessian (projected Newton): through the energy's closed-form eigensystem
// where it has one and filter.analytic is set, else by the numeric eigensolve of psd_projection.hpp.
template <int R, int C>
inline kernels::Derivs<R * C> evaluateFilteredEnergy(const Material &m, const CellData<C> &cell, const Mat<R, C> &F,
                                                     const HessianFilter &filter) {
  return evaluateEnergy<R, C>(m, cell, F, kernels::Order::Hessian, &filter);
}

// The singularity measure alpha at F (the line-search safeguard's quantity).
template <int R, int C>
inline double elementAlpha(const Mat<R, C> &F) {
  return kernels::rootValue(F).alpha;
}

}  // namespace aries::energies
