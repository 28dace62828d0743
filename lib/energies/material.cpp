#include "energies/material.hpp"

#include "energies/registry.hpp"

#include <cmath>
#include <sstream>

namespace aries::energies {

namespace {
bool finite(double x) { return std::isfinite(x); }
}  // namespace

const char *shapeName(ElementShape s) {
  switch (s) {
    case ElementShape::Tet: return "tetrahedral (3x3 F)";
    case ElementShape::Planar: return "planar triangle (2x2 F)";
    case ElementShape::Cloth: return "cloth triangle (3x2 F)";
  }
  return "?";
}

std::optional<EnergyKind> energyFromName(std::string_view name) {
  for (const auto &e : kEnergyRegistry)
    if (name == e.name) return e.kind;
  return std::nullopt;
}
const char *energyName(EnergyKind kind) { return energyInfo(kind).name; }
std::string energyNames() {
  std::string s;
  for (const auto &e : kEnergyRegistry) {
    if (!s.empty()) s += '|';
    s += e.name;
  }
  return s;
}

std::optional<SingularityMode> singularityFromName(std::string_view name) {
  if (name == "none") return SingularityMode::None;
  if (name == "mollifier") return SingularityMode::Mollifier;
  if (name == "barrier") return SingularityMode::Barrier;
  return std::nullopt;
}
const char *singularityName(SingularityMode mode) {
  switch (mode) {
    case SingularityMode::None: return "none";
    case SingularityMode::Mollifier: return "mollifier";
    case SingularityMode::Barrier: return "barrier";
  }
  return "?";
}

bool energyContainsStretchInvariant(EnergyKind kind) { return energyInfo(kind).stretch; }
bool energySupportsShape(EnergyKind kind, ElementShape shape) { return energyInfo(kind).supports(shape); }
bool energyUsesFibers(EnergyKind kind) { return energyInfo(kind).fibers; }
bool energyHasAnisotropicStretchTerms(EnergyKind kind) {
  return energyInfo(kind).stretch && !energyInfo(kind).isotropic;
}
bool energyUsesVolumeTerm(EnergyKind kind) { return energyInfo(kind).volume; }
CellField energyCellField(EnergyKind kind) { return energyInfo(kind).cellField; }

double lameMu(double E, double nu) { return E / (2.0 * (1.0 + nu)); }
double lameLambda(double E, double nu) { return E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)); }

std::string finalizeMaterial(Material &m, ElementShape shape) {
  std::ostringstream err;
  const EnergyInfo &info = energyInfo(m.kind);
  const char *name = info.name;
  if (!energySupportsShape(m.kind, shape)) {
    err << "energy '" << name << "' is not defined for " << shapeName(shape) << " elements";
    return err.str();
  }
  const bool cloth = shape == ElementShape::Cloth;
  const int dim = shape == ElementShape::Tet ? 3 : 2;
  if (cloth) {
    if (!finite(m.mu1) || m.mu1 <= 0.0) return std::string("energy '") + name + "' needs -mu1 > 0 (stretch stiffness)";
    if (info.mu2 && (!finite(m.mu2) || m.mu2 < 0.0))
      return std::string("energy '") + name + "' needs -mu2 >= 0 (shear stiffness)";
  } else {
    if (!finite(m.mu) || m.mu < 0.0 || (m.mu == 0.0 && info.shear))
      return std::string("energy '") + name + "' needs a shear modulus: give -E and -nu, or -mu (> 0)";
    if (!finite(m.lambda) || m.lambda < 0.0) return "-lambda must be a finite number >= 0 (or give -nu in [0, 0.5))";
  }
  // Orthonormal basis for iarap / ortho / kim_aa (rows are orthonormal by construction in the options parser; check).
  const Eigen::Matrix3d BBt = m.basis * m.basis.transpose();
  if (!(BBt - Eigen::Matrix3d::Identity()).isZero(1e-10)) return "the material basis is not orthonormal";
  if (dim == 2 && (std::abs(m.basis(0, 2)) > 1e-12 || std::abs(m.basis(1, 2)) > 1e-12))
    return "planar elements need basis directions in the xy plane (z component 0)";

  // The energy's own checks and precomputation (the layered-ARAP weight tensor W, weighted_arap.hpp).
  m.weight3.setZero();
  m.weight2.setZero();
  const std::string own = info.finalize(m, dim);
  if (!own.empty()) return own;

  SingularityParams &sp = m.singularity;
  if (!finite(sp.mollifier.eps) || sp.mollifier.eps <= 0.0) return "-mollifier_eps must be > 0";
  if (!finite(sp.mollifier.proxy)) return "-mollifier_proxy must be finite";
  if (!finite(sp.barrier.eps) || sp.barrier.eps <= 0.0) return "-barrier_eps must be > 0";
  if (!finite(sp.barrierStiffness) || sp.barrierStiffness < 0.0) return "-barrier_stiffness must be >= 0";
  if (!energyContainsStretchInvariant(m.kind)) {
    sp.mode = SingularityMode::None;  // nothing to fix; the options layer rejects an explicit -singularity
  } else if (sp.barrierStiffness == 0.0) {
    sp.barrierStiffness = cloth ? m.mu1 : (m.mu > 0.0 ? m.mu : m.weight3.trace() / 3.0);
  }
  return {};
}

}  // namespace aries::energies
