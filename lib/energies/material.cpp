#include "energies/material.hpp"

#include <cmath>
#include <sstream>

namespace aries::energies {

namespace {
struct EnergyInfo {
  EnergyKind kind;
  const char *name;
  bool stretch;  // contains I4 / I6
  bool tet, planar, cloth;
  bool fibers;
  bool volume;
};
constexpr EnergyInfo kEnergies[] = {
    {EnergyKind::Alx, "alx", true, true, true, false, true, false},
    {EnergyKind::Iarap, "iarap", true, true, true, false, false, true},
    {EnergyKind::IarapLin, "iarap_lin", false, true, true, false, false, true},
    {EnergyKind::ArapSvd, "arap_svd", false, true, true, false, false, true},
    {EnergyKind::Ortho, "ortho", true, true, true, false, false, true},
    {EnergyKind::Aniso, "aniso", true, true, true, false, false, true},
    {EnergyKind::Fiber, "fiber", true, true, true, false, true, true},
    {EnergyKind::KimAA, "kim_aa", false, true, true, false, false, true},
    {EnergyKind::Bw, "bw", false, false, false, true, true, false},
    {EnergyKind::Bw46, "bw46", false, false, false, true, false, false},
    {EnergyKind::Bw461, "bw461", true, false, false, true, true, false},
    {EnergyKind::Bw46s, "bw46s", true, false, false, true, true, false},
    {EnergyKind::ShapeTarget, "shape_target", true, true, true, false, false, true},
    {EnergyKind::Caricature, "caricature", true, true, false, false, true, true},
};
const EnergyInfo &info(EnergyKind k) {
  for (const auto &e : kEnergies)
    if (e.kind == k) return e;
  return kEnergies[0];
}
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
  for (const auto &e : kEnergies)
    if (name == e.name) return e.kind;
  return std::nullopt;
}
const char *energyName(EnergyKind kind) { return info(kind).name; }
std::string energyNames() {
  std::string s;
  for (const auto &e : kEnergies) {
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

bool energyContainsStretchInvariant(EnergyKind kind) { return info(kind).stretch; }
bool energySupportsShape(EnergyKind kind, ElementShape shape) {
  const auto &e = info(kind);
  return shape == ElementShape::Tet ? e.tet : shape == ElementShape::Planar ? e.planar : e.cloth;
}
bool energyUsesFibers(EnergyKind kind) { return info(kind).fibers; }
bool energyUsesVolumeTerm(EnergyKind kind) { return info(kind).volume; }

double lameMu(double E, double nu) { return E / (2.0 * (1.0 + nu)); }
double lameLambda(double E, double nu) { return E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)); }

std::string finalizeMaterial(Material &m, ElementShape shape) {
  std::ostringstream err;
  const char *name = energyName(m.kind);
  if (!energySupportsShape(m.kind, shape)) {
    err << "energy '" << name << "' is not defined for " << shapeName(shape) << " elements";
    return err.str();
  }
  const bool cloth = shape == ElementShape::Cloth;
  const int dim = shape == ElementShape::Tet ? 3 : 2;
  if (cloth) {
    if (!finite(m.mu1) || m.mu1 <= 0.0) return std::string("energy '") + name + "' needs -mu1 > 0 (stretch stiffness)";
    if (m.kind != EnergyKind::Bw46 && (!finite(m.mu2) || m.mu2 < 0.0))
      return std::string("energy '") + name + "' needs -mu2 >= 0 (shear stiffness)";
  } else {
    if (!finite(m.mu) || m.mu < 0.0 || (m.mu == 0.0 && m.kind != EnergyKind::Ortho && m.kind != EnergyKind::Aniso))
      return std::string("energy '") + name + "' needs a shear modulus: give -E and -nu, or -mu (> 0)";
    if (!finite(m.lambda) || m.lambda < 0.0) return "-lambda must be a finite number >= 0 (or give -nu in [0, 0.5))";
  }
  if (m.kind == EnergyKind::Fiber && (!finite(m.gamma) || m.gamma < 0.0))
    return "energy 'fiber' needs -gamma >= 0 (fiber stiffness)";
  if (m.kind == EnergyKind::Caricature && !finite(m.beta)) return "energy 'caricature' needs a finite -beta";

  // Orthonormal basis for iarap / ortho / kim_aa (rows are orthonormal by construction in the options parser; check).
  const Eigen::Matrix3d BBt = m.basis * m.basis.transpose();
  if (!(BBt - Eigen::Matrix3d::Identity()).isZero(1e-10)) return "the material basis is not orthonormal";
  if (dim == 2 && (std::abs(m.basis(0, 2)) > 1e-12 || std::abs(m.basis(1, 2)) > 1e-12))
    return "planar elements need basis directions in the xy plane (z component 0)";

  m.weight3.setZero();
  m.weight2.setZero();
  auto addDirection = [&](const Eigen::Vector3d &u, double c) {
    m.weight3 += c * u * u.transpose();
    m.weight2 += c * u.head<2>() * u.head<2>().transpose();
  };
  switch (m.kind) {
    case EnergyKind::Iarap:
    case EnergyKind::Fiber:
    case EnergyKind::Caricature:
      for (int k = 0; k < dim; ++k) addDirection(m.basis.row(k).transpose(), m.mu);
      break;
    case EnergyKind::Ortho:
      for (int k = 0; k < dim; ++k) {
        if (!finite(m.basisCoeffs[k]) || m.basisCoeffs[k] < 0.0)
          return "energy 'ortho' needs -ortho_mu with one value >= 0 per direction";
        addDirection(m.basis.row(k).transpose(), m.basisCoeffs[k]);
      }
      break;
    case EnergyKind::Aniso:
      if (m.numDirections < 1 || m.numDirections > kMaxDirections)
        return "energy 'aniso' needs -aniso_dirs with 1 to 8 directions and -aniso_mu with one coefficient each";
      for (int k = 0; k < m.numDirections; ++k) {
        Eigen::Vector3d d = m.directions[k];
        if (dim == 2 && std::abs(d[2]) > 1e-12) return "planar elements need -aniso_dirs in the xy plane (z = 0)";
        if (!(d.norm() > 0.0) || !finite(d.norm())) return "-aniso_dirs contains a zero-length or non-finite direction";
        if (!finite(m.directionCoeffs[k]) || m.directionCoeffs[k] < 0.0) return "-aniso_mu coefficients must be >= 0";
        addDirection(d.normalized(), m.directionCoeffs[k]);
      }
      break;
    default:
      break;
  }

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
