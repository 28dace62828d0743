// Stress and strain measures for output (-output_fields), from an element's deformation gradient and first
// Piola-Kirchhoff stress. Not used by the solver: these are what a mechanics user post-processes.
//
// Every element shape is reported in the mesh's 3D frame, as 3x3 tensors. An element's F maps its material chart
// (C coordinates) to space (R coordinates); `Frest` (3 x C) maps the chart to the rest shape in 3D. The chart is
// orthonormal (tets: the identity, planar triangles: the xy plane, cloth: an orthonormal frame of the rest triangle's
// plane), so with Fs = F Frest^T (R x 3, the deformation gradient from rest space to current space):
//   deformation gradient  Fs                                      (rows beyond R are 0)
//   PK1                   P Frest^T                               (P = dPsi/dF, energy per unit rest measure)
//   J                     det F (square F, signed), sqrt(det(F^T F)) (cloth: the area ratio)
//   Cauchy                P F^T / J                               (R x R: frame independent; planar = plane stress)
//   von Mises             sqrt(3/2 s:s), s = sigma - tr(sigma)/3 I (of the 3x3 Cauchy stress)
//   Green-Lagrange        (Fs^T Fs - Frest Frest^T) / 2           (rest frame; for triangles the in-plane part)
//   principal stretches   singular values of F, descending; for square F with det F < 0 the smallest is negative
//                         (the paper's signed singular values, Sec. 3); triangles report 1 as the third
// For triangles energies are per unit rest area, so stresses are forces per unit length (membrane stresses).
// A cell with J = 0 has no Cauchy stress (NaN).
#pragma once

#include "kernels/dense_decompositions.hpp"
#include "kernels/types.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace aries::kernels {

struct StressMeasures {
  Mat<3, 3> deformationGradient = Mat<3, 3>::Zero();
  Mat<3, 3> pk1 = Mat<3, 3>::Zero();
  Mat<3, 3> cauchy = Mat<3, 3>::Zero();
  Mat<3, 3> greenLagrange = Mat<3, 3>::Zero();
  Vec<3> principalStretches = Vec<3>::Ones();
  double J = 1.0;
  double vonMises = 0.0;

  // An element evaluated at several points reports the average of each measure over its points: start from zero()
  // and add each point's measures times its share of the element's rest measure.
  static StressMeasures zero() {
    StressMeasures m;
    m.principalStretches.setZero();
    m.J = 0.0;
    return m;
  }
  void accumulate(const StressMeasures &o, double w) {
    deformationGradient += w * o.deformationGradient;
    pk1 += w * o.pk1;
    cauchy += w * o.cauchy;
    greenLagrange += w * o.greenLagrange;
    principalStretches += w * o.principalStretches;
    J += w * o.J;
    vonMises += w * o.vonMises;
  }
};

template <int R, int C>
inline double areaOrVolumeRatio(const Mat<R, C> &F) {
  if constexpr (R == C) return F.determinant();
  else return std::sqrt(std::max(0.0, (F.transpose() * F).determinant()));
}

inline double vonMisesStress(const Mat<3, 3> &sigma) {
  const Mat<3, 3> s = sigma - sigma.trace() / 3.0 * Mat<3, 3>::Identity();
  return std::sqrt(1.5 * s.squaredNorm());
}

// F and P in the element's chart (R x C), Frest the chart's map to the rest shape (3 x C, orthonormal columns).
template <int R, int C>
inline StressMeasures stressMeasures(const Mat<R, C> &F, const Mat<R, C> &P, const Mat<3, C> &Frest) {
  StressMeasures m;
  const Mat<R, 3> Fs = F * Frest.transpose();
  m.deformationGradient.template topRows<R>() = Fs;
  m.pk1.template topRows<R>() = P * Frest.transpose();
  m.J = areaOrVolumeRatio<R, C>(F);
  if (m.J != 0.0)
    m.cauchy.template topLeftCorner<R, R>() = P * F.transpose() / m.J;
  else
    m.cauchy.setConstant(std::numeric_limits<double>::quiet_NaN());
  m.vonMises = vonMisesStress(m.cauchy);
  m.greenLagrange = 0.5 * (Fs.transpose() * Fs - Frest * Frest.transpose());
  const Vec<C> s = singularValues<R, C>(F);  // descending
  m.principalStretches.template head<C>() = s;
  if constexpr (R == C)
    if (m.J < 0.0) m.principalStretches[C - 1] = -s[C - 1];
  return m;
}

}  // namespace aries::kernels
