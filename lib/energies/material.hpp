// Material description shared by every energy: which energy, its parameters, the singularity mode, and the
// per-element anisotropy data (fibers, shape targets, curvature). Pure C++: parsing from PETSc options lives in
// lib/fem/material_options.*, so the kernels and energies stay free of PETSc.
//
// Parameter conventions (a contract, see docs/energies.md):
//   iarap      = mu |F - R|^2 + lambda/2 (J - 1)^2, summed over an orthonormal basis as in Eq. 39 (each direction
//                term is alx with coefficient 2 mu); small strain -> linear elasticity with (E, nu).
//   alx        = mu/2 (I5(a) - 2 I4(a) + 1)                                   (Eq. 38)
//   ortho      = sum_k mu_k |(F - R) u_k|^2 + lambda/2 (J - 1)^2              (orthonormal u_k; mu_k = mu -> iarap)
//   aniso      = sum_k c_k |(F - R) d_k|^2 + lambda/2 (J - 1)^2               (any unit d_k)
//   shape_target = mu/2 |F - R S_t|^2 + lambda/2 (J - det S_t)^2 in the Eq. 65 form (note: mu/2, Eq. 54's scale)
#pragma once

#include "energies/energy_list.hpp"
#include "kernels/aberration_barrier.hpp"
#include "kernels/mollifier.hpp"

#include <array>
#include <optional>
#include <string>
#include <string_view>

namespace aries::energies {

using kernels::Mat;
using kernels::Vec;

// The energies of the registry (energy_list.hpp), one id each.
enum class EnergyKind {
#define ARIES_ENERGY_ID(Name) Name,
  ARIES_ENERGIES(ARIES_ENERGY_ID)
#undef ARIES_ENERGY_ID
};
#define ARIES_ENERGY_COUNT(Name) +1
inline constexpr int kEnergyCount = 0 ARIES_ENERGIES(ARIES_ENERGY_COUNT);
#undef ARIES_ENERGY_COUNT

enum class SingularityMode { None, Mollifier, Barrier };

struct SingularityParams {
  SingularityMode mode = SingularityMode::Mollifier;
  kernels::MollifierParams mollifier;  // eps = 1e-3, proxy c = 0
  kernels::BarrierParams barrier;      // eps = 1e-2
  double barrierStiffness = 0.0;       // kappa in kappa b(alpha); resolved to the energy's modulus by finalize()
};

// Element shapes by F's size.
enum class ElementShape { Tet, Planar, Cloth };  // 3x3, 2x2, 3x2
const char *shapeName(ElementShape s);

constexpr int kMaxDirections = 8;

// Eigen's fixed-size vectors are not zeroed by value-initialization ({}): the unused directions would be copied
// uninitialized with every Material.
inline std::array<Eigen::Vector3d, kMaxDirections> zeroDirections() {
  std::array<Eigen::Vector3d, kMaxDirections> d;
  d.fill(Eigen::Vector3d::Zero());
  return d;
}

struct Material {
  EnergyKind kind = EnergyKind::Iarap;
  double mu = 0.0, lambda = 0.0;  // Lame parameters
  double gamma = 0.0;             // fiber stiffening
  double mu1 = 0.0, mu2 = 0.0;    // cloth stretch / shear
  double beta = 0.0;              // caricature strength
  // Orthonormal basis (rows u_k, material frame) for iarap / ortho / kim_aa and per-direction coefficients (ortho).
  Eigen::Matrix3d basis = Eigen::Matrix3d::Identity();
  Eigen::Vector3d basisCoeffs = Eigen::Vector3d::Zero();
  // Free directions for aniso.
  std::array<Eigen::Vector3d, kMaxDirections> directions = zeroDirections();
  std::array<double, kMaxDirections> directionCoeffs{};
  int numDirections = 0;
  SingularityParams singularity;

  // Weight tensors W of the layered ARAP term (weighted_arap.hpp) for 3D and planar elements, set by finalize().
  Eigen::Matrix3d weight3 = Eigen::Matrix3d::Zero();
  Eigen::Matrix2d weight2 = Eigen::Matrix2d::Zero();
};

// Element data that options can set uniformly (the FE layer may override it per cell from files).
struct UniformCellData {
  Eigen::Vector3d a = Eigen::Vector3d::UnitX();          // -fiber
  Eigen::Vector3d b = Eigen::Vector3d::UnitY();          // -fiber2
  Eigen::Matrix3d target = Eigen::Matrix3d::Identity();  // -target (shape_target)
  double curvature = 1.0;                                // -curvature (caricature)
  bool fiberGiven = false;
};

// Per-element anisotropy data in the material frame (Cols = 3 for tets, 2 for planar and cloth elements).
template <int C>
struct CellData {
  Vec<C> a = Vec<C>::UnitX();                   // fiber (alx, fiber, kim_aa basis, cloth a, caricature normal n)
  Vec<C> b = Vec<C>::UnitY();                   // second fiber (cloth)
  Mat<C, C> target = Mat<C, C>::Identity();     // shape target S_t
  double curvature = 0.0;                       // caricature ratio c
};

std::optional<EnergyKind> energyFromName(std::string_view name);
const char *energyName(EnergyKind kind);
std::string energyNames();  // "alx|iarap|..." for messages
std::optional<SingularityMode> singularityFromName(std::string_view name);
const char *singularityName(SingularityMode mode);

bool energyContainsStretchInvariant(EnergyKind kind);  // has I4/I6 terms, i.e. -singularity applies
bool energySupportsShape(EnergyKind kind, ElementShape shape);
bool energyUsesFibers(EnergyKind kind);       // reads CellData::a (and b for cloth)
// Has I4/I6 terms that weigh directions differently (every stretch energy but iarap: fibers, a basis with its own
// moduli, layered directions, shape targets).
bool energyHasAnisotropicStretchTerms(EnergyKind kind);
bool energyUsesVolumeTerm(EnergyKind kind);   // has lambda/2 (J - J0)^2 (square F only)

// A per-cell field an energy's elements take from the mesh rather than from options; the solver computes it
// (fem/cell_fields.hpp: one source per field): shape targets S_t per cell from -activation / -target_file, varying
// with the load or in time (Sec. 5); the caricature's curvature ratio c and normal n from the rest surface (Sec. 6).
enum class CellField { None, ShapeTargets, SurfaceCurvature };
CellField energyCellField(EnergyKind kind);

// Lame parameters from Young's modulus and Poisson's ratio (3D / plane strain).
double lameMu(double E, double nu);
double lameLambda(double E, double nu);

// Checks the parameters for the element shape and precomputes the weight tensors and the barrier stiffness.
// Returns an empty string on success, otherwise one sentence saying what is wrong and what to do.
std::string finalizeMaterial(Material &m, ElementShape shape);

}  // namespace aries::energies
