// Everything one material point reports at one F: value, PK1 and Hessian of the energy, the Hessian as projected
// Newton filters it, the root function's f and alpha, and the stretch invariants I4(a) / I6(a, b) where the energy
// reads fibers. One definition for the tools that report a point: aries-matpoint -json and the Python module
// (python/aries_kernels.cpp), so both give the same numbers in the same orderings. Pure C++: no PETSc.
#pragma once

#include "energies/energy.hpp"

#include <cmath>

namespace aries::energies {

template <int R, int C>
struct PointEvaluation {
  static constexpr int N = R * C;
  kernels::Derivs<N> derivs;          // value, PK1 (row-major flattened F-gradient), Hessian in that order
  kernels::Mat<N, N> projected;       // the filtered Hessian (or the Hessian itself when no filter is asked)
  double f = NAN, alpha = NAN;        // the root function's I1 and the singularity measure (kernels/root_function)
  double I4 = NAN, I6 = NAN;          // NaN where hasI4 / hasI6 is false
  bool hasI4 = false, hasI6 = false;  // I4: energies that read fibers; I6: those on cloth (3x2) elements too
};

// Which invariants a point reports: I4 where the energy reads fibers, I6 where it does on cloth (3x2) elements.
inline bool reportsI4(EnergyKind kind) { return energyUsesFibers(kind); }
template <int R, int C>
inline bool reportsI6(EnergyKind kind) {
  return reportsI4(kind) && R == 3 && C == 2;
}

// `filter` nullptr: `projected` is the unfiltered Hessian. `rawHessian` false (with a filter): one pass gives the
// value, PK1 and the filtered Hessian, and derivs.hess is the filtered one too (half the work where only the
// projected Hessian is wanted).
template <int R, int C>
inline PointEvaluation<R, C> evaluatePoint(const Material &m, const CellData<C> &cell, const kernels::Mat<R, C> &F,
                                           const HessianFilter *filter, bool rawHessian = true) {
  PointEvaluation<R, C> p;
  if (filter && !rawHessian) {
    p.derivs = evaluateFilteredEnergy<R, C>(m, cell, F, *filter);
    p.projected = p.derivs.hess;
  } else {
    p.derivs = evaluateEnergy<R, C>(m, cell, F);
    p.projected = filter ? evaluateFilteredEnergy<R, C>(m, cell, F, *filter).hess : p.derivs.hess;
  }
  const kernels::RootValue root = kernels::rootValue(F);
  p.f = root.f;
  p.alpha = root.alpha;
  p.hasI4 = reportsI4(m.kind);
  p.hasI6 = reportsI6<R, C>(m.kind);
  if (p.hasI4 || p.hasI6) {
    const auto ctx = kernels::makeRootContext<R, C>(F, kernels::Order::Value);
    if (p.hasI4) p.I4 = kernels::stretchInvariantValue<R, C>(ctx, kernels::fiberTensor<C>(cell.a));
    if (p.hasI6) p.I6 = kernels::stretchInvariantValue<R, C>(ctx, kernels::crossFiberTensor<C>(cell.a, cell.b));
  }
  return p;
}

}  // namespace aries::energies
