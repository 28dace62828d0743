// Energy density Psi(F) of a material at one element: value, PK1 (flattened gradient) and Hessian, plus the PSD
// projection used by projected Newton. The material must have passed finalizeMaterial() for this element shape.
#pragma once

#include "energies/registry.hpp"

namespace aries::energies {

// `filter` (optional, with Order::Hessian): the Hessian is returned eigenvalue-filtered (evaluateFilteredEnergy).
template <int R, int C>
inline kernels::Derivs<R * C> evaluateEnergy(const Material &m, const CellData<C> &cell, const Mat<R, C> &F,
                                             kernels::Order order = kernels::Order::Hessian,
                                             const HessianFilter *filter = nullptr) {
  return evaluateRegistered<R, C>(EnergyInput<R, C>{m, cell, F, order, filter});
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
