// What an energy of the registry (energies/registry.hpp) is: one struct in one header of energies/catalog/ with
//   name, summary            the -energy value and one line for -help and the docs
//   tet, planar, cloth       the element shapes it is defined for (3x3, 2x2, 3x2 F)
//   flags                    stretch (has I4/I6 terms: -singularity applies), fibers (reads the fiber a, and b on
//                            cloth), basis (an orthonormal basis from -fiber/-fiber2), volume (lambda/2 (J - J0)^2),
//                            shear (tets/planar: needs mu > 0), mu2 (cloth: reads -mu2), isotropic (its I4/I6 terms
//                            weigh every direction alike, Eq. 39: the band default of degenerate dynamic starts, below)
//   cellField                a per-cell field the solver computes from the mesh for it (CellField: shape targets,
//                            surface curvature); fem/cell_fields.hpp provides each
//   params                   its own options with help strings (ParamSpec), read by fem/material_options.cpp
//   finalize(m, dim)         checks its parameters, precomputes (the layered-ARAP weight tensor); "" when fine
//   evaluate<R, C>(in)       value, PK1 and Hessian at F in one pass (filtered for projected Newton when asked)
// EnergyDefaults holds the defaults, so a descriptor states only what differs. Pure C++: no PETSc.
#pragma once

#include "energies/material.hpp"
#include "energies/singularity.hpp"
#include "energies/volume_term.hpp"
#include "energies/weighted_arap.hpp"
#include "kernels/psd_projection.hpp"

#include <array>
#include <string>
#include <utility>

namespace aries::energies {

// How projected Newton filters an element's F-space Hessian (Newton options -psd_projection, -psd_eigensystem):
// the eigenvalue filter and whether an energy's closed-form eigensystem is used where it has one (isotropic ARAP on
// tetrahedra outside the singularity fix's band; everything else: the numeric 9x9 / 6x6 / 4x4 eigensolve).
struct HessianFilter {
  kernels::EigenFilter filter = kernels::EigenFilter::Clamp;
  bool analytic = true;
};

// One option of an energy. Real: a Material member; CellReal: a UniformCellData member; PerAxis: one value per basis
// direction (Material::basisCoeffs); Directions: `option` lists directions (dim numbers each) and `option2` one
// coefficient per direction (Material::directions, directionCoeffs); SymmetricMatrix: a dim x dim row-major
// symmetric matrix (UniformCellData::target).
enum class ParamKind { Real, CellReal, PerAxis, Directions, SymmetricMatrix };

struct ParamSpec {
  const char *option;
  const char *help;
  ParamKind kind = ParamKind::Real;
  double Material::*real = nullptr;
  double UniformCellData::*cellReal = nullptr;
  bool required = false;  // must be given (a region inherits it from a global material of the same energy)
  const char *option2 = nullptr;
};

struct EnergyDefaults {
  static constexpr bool tet = true, planar = true, cloth = false;
  static constexpr bool stretch = false, fibers = false, basis = false, volume = false, shear = true, mu2 = true;
  static constexpr bool isotropic = false;
  static constexpr CellField cellField = CellField::None;
  static constexpr std::array<ParamSpec, 0> params{};
  static std::string finalize(Material &, int /*dim*/) { return {}; }
};

// The arguments of evaluate: material, per-element data, F, the derivative order, and (optional, with
// Order::Hessian) the Hessian filter of projected Newton.
template <int R, int C>
struct EnergyInput {
  const Material &m;
  const CellData<C> &cell;
  const Mat<R, C> &F;
  kernels::Order order;
  const HessianFilter *filter;
  bool filtered() const { return filter && kernels::wants(order, kernels::Order::Hessian); }
  // The numeric eigenvalue filter (psd_projection.hpp), for energies without a closed-form eigensystem.
  void filterNumerically(kernels::Derivs<R * C> &d) const {
    if (filtered()) d.hess = kernels::filterEigenvalues<R * C>(d.hess, filter->filter);
  }
  kernels::Derivs<R * C> finish(kernels::Derivs<R * C> &&d) const {
    filterNumerically(d);
    return std::move(d);
  }
};

// The frame of the energies built on the analytic rotation (kernels/root_function.hpp): the root context and the
// I4/I6 terms with the material's singularity fix (Eq. 33's mollifier or the Sec. 7.1 barrier); body(ctx, terms, out)
// sets the energy's terms, then the barrier term is added and the Hessian filtered.
template <int R, int C, class Body>
inline kernels::Derivs<R * C> rootEnergy(const EnergyInput<R, C> &in, Body &&body) {
  const auto ctx = kernels::makeRootContext<R, C>(in.F, in.order);
  const StretchTerms<R, C> terms(ctx, in.m.singularity);
  kernels::Derivs<R * C> out;
  body(ctx, terms, out);
  out += terms.barrier();
  return in.finish(std::move(out));
}

// lambda/2 (J - J0)^2 (Eq. 39's volume term) for square F with lambda != 0.
template <int R, int C>
inline void addVolume(const EnergyInput<R, C> &in, const kernels::RootContext<R, C> &ctx, double J0,
                      kernels::Derivs<R * C> &out) {
  if constexpr (R == C)
    if (in.m.lambda != 0.0) out += volumeTerm<R * C>(jacobianOf<R>(ctx), in.m.lambda, J0, in.order);
}

// The layered-ARAP weight W = sum_k c_k u_k u_k^T (weighted_arap.hpp) of the material, for 3D and planar elements.
template <int C>
inline const Mat<C, C> &materialWeight(const Material &m) {
  if constexpr (C == 3)
    return m.weight3;
  else
    return m.weight2;
}
inline void addWeightDirection(Material &m, const Eigen::Vector3d &u, double c) {
  m.weight3 += c * u * u.transpose();
  m.weight2 += c * u.head<2>() * u.head<2>().transpose();
}
// The layered ARAP energies (iarap, ortho, aniso): the weighted term with the material's W + lambda/2 (J - 1)^2.
template <int R, int C>
inline kernels::Derivs<R * C> layeredArap(const EnergyInput<R, C> &in) {
  return rootEnergy(in, [&](const auto &ctx, const auto &terms, auto &out) {
    out = weightedArap<R, C>(ctx, terms, materialWeight<C>(in.m));
    addVolume(in, ctx, 1.0, out);
  });
}

// W = mu sum_k u_k u_k^T over the material basis (iarap and the energies built on it).
inline std::string isotropicWeight(Material &m, int dim) {
  for (int k = 0; k < dim; ++k) addWeightDirection(m, m.basis.row(k).transpose(), m.mu);
  return {};
}

}  // namespace aries::energies
