#include "fem/material_options.hpp"

#include "energies/registry.hpp"
#include "core/options.hpp"
#include "fem/fem_options.hpp"

namespace aries::fem {

using core::optionName;
using core::optionReal;
using core::optionRealList;
using core::OptionDecl;
using core::ReadContext;

using energies::ElementShape;
using energies::EnergyKind;

namespace {

PetscErrorCode readDirection(const OptionDecl &decl, ReadContext at, ElementShape shape, Eigen::Vector3d *dir,
                             PetscBool *set) {
  std::vector<PetscReal> v;
  const bool threeD = shape == ElementShape::Tet;
  const char *prefix = at.prefix, *name = decl.name;
  PetscFunctionBeginUser;
  PetscCall(core::get(decl, &v, set, at));
  if (threeD && !v.empty() && v.size() != 3)
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s takes 3 comma-separated numbers for tetrahedra, got %d",
            optionName(prefix, name).c_str(), (int)v.size());
  if (!v.empty()) {
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < v.size(); ++i) d[i] = v[i];
    if (!threeD && d[2] != 0.0)
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
              "option %s: 2D elements take directions in their material plane (x,y) or with z = 0",
              optionName(prefix, name).c_str());
    if (!(d.norm() > 0.0))
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s: a direction must not be zero",
              optionName(prefix, name).c_str());
    *dir = d.normalized();
  }
  PetscFunctionReturn(0);
}

// Orthonormal basis with u1 = a and u2 = b orthogonalized against a.
PetscErrorCode basisFrom(const Eigen::Vector3d &a, const Eigen::Vector3d &b, const char *prefix,
                         Eigen::Matrix3d *basis) {
  PetscFunctionBeginUser;
  Eigen::Vector3d u2 = b - a.dot(b) * a;
  if (!(u2.norm() > 1e-8))
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "options %s and %s must not be parallel (they define the basis)",
            optionName(prefix, "-fiber").c_str(), optionName(prefix, "-fiber2").c_str());
  u2.normalize();
  basis->row(0) = a.transpose();
  basis->row(1) = u2.transpose();
  basis->row(2) = a.cross(u2).transpose();
  PetscFunctionReturn(0);
}

// The options an energy declares (energies/descriptor.hpp, ParamSpec). `inherited`: a region starting from a global
// material of the same energy, whose values stand where an option is not given.
PetscErrorCode readEnergyParams(const char *prefix, const energies::EnergyInfo &info, int dim, bool inherited,
                                energies::Material *m, UniformCellData *c) {
  PetscFunctionBeginUser;
  for (int k = 0; k < info.numParams; ++k) {
    const energies::ParamSpec &p = info.params[k];
    const std::string opt = optionName(prefix, p.option);
    PetscBool set = PETSC_FALSE;
    std::vector<PetscReal> v;
    switch (p.kind) {
      case energies::ParamKind::Real:
        PetscCall(optionReal(prefix, p.option, &(m->*p.real), &set));
        break;
      case energies::ParamKind::CellReal:
        PetscCall(optionReal(prefix, p.option, &(c->*p.cellReal), &set));
        break;
      case energies::ParamKind::PerAxis:
        PetscCall(optionRealList(prefix, p.option, &v, &set, dim));
        for (size_t i = 0; i < v.size(); ++i) m->basisCoeffs[i] = v[i];
        break;
      case energies::ParamKind::Directions: {
        std::vector<PetscReal> coeffs;
        PetscBool setCoeffs = PETSC_FALSE;
        PetscCall(optionRealList(prefix, p.option, &v, &set, -1));
        PetscCall(optionRealList(prefix, p.option2, &coeffs, &setCoeffs, -1));
        if (!set && !setCoeffs && inherited) break;
        const int n = static_cast<int>(coeffs.size());
        if (!set || !setCoeffs || n < 1 || n > energies::kMaxDirections || v.size() != static_cast<size_t>(n * dim))
          SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
                  "energy '%s' needs %s with 1..%d directions of %d components each and %s with one coefficient per "
                  "direction",
                  info.name, opt.c_str(), energies::kMaxDirections, dim, optionName(prefix, p.option2).c_str());
        m->numDirections = n;
        for (int d = 0; d < n; ++d) {
          m->directions[d] = Eigen::Vector3d::Zero();
          for (int i = 0; i < dim; ++i) m->directions[d][i] = v[d * dim + i];
          m->directionCoeffs[d] = coeffs[d];
        }
        set = PETSC_TRUE;
        break;
      }
      case energies::ParamKind::SymmetricMatrix: {
        PetscCall(optionRealList(prefix, p.option, &v, &set, dim * dim));
        if (!set) break;
        Eigen::Matrix3d T = Eigen::Matrix3d::Identity();
        for (int i = 0; i < dim; ++i)
          for (int j = 0; j < dim; ++j) T(i, j) = v[i * dim + j];
        if (!(T - T.transpose()).isZero(1e-12 * (1.0 + T.norm())))
          SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s must be a symmetric matrix", opt.c_str());
        c->target = T;
        break;
      }
    }
    if (!set && p.required && !inherited)
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "energy '%s' needs %s: %s", info.name, opt.c_str(), p.help);
  }
  PetscFunctionReturn(0);
}

// Moduli: cloth -mu1 (stretch) and -mu2 (shear, where the energy has it), default 20 each; otherwise -E/-nu
// (default 1e4, 0.3) or -mu/-lambda, not both; a region keeps its base's moduli unless it gives its own.
PetscErrorCode readModuli(const char *prefix, bool cloth, const energies::Material *base, energies::Material *m) {
  PetscFunctionBeginUser;
  const ReadContext at{prefix, nullptr, base != nullptr};
  if (cloth) {
    // An energy without a shear term keeps -mu2's default: it enters the modulus that scales contact (max(mu1, mu2)).
    if (!base) PetscCall(core::getDefault(opt::clothShear, &m->mu2));
    PetscCall(core::get(opt::clothStretch, &m->mu1, nullptr, at));
    if (energies::energyInfo(m->kind).mu2) PetscCall(core::get(opt::clothShear, &m->mu2, nullptr, at));
  } else {
    PetscReal E = 0.0, nu = 0.0;
    PetscBool hasE = PETSC_FALSE, hasNu = PETSC_FALSE, hasMu = PETSC_FALSE, hasLambda = PETSC_FALSE;
    PetscCall(core::get(opt::youngsModulus, &E, &hasE, {prefix}));
    PetscCall(core::get(opt::poissonRatio, &nu, &hasNu, {prefix}));
    PetscCall(core::get(opt::lameMu, &m->mu, &hasMu, at));
    PetscCall(core::get(opt::lameLambda, &m->lambda, &hasLambda, at));
    if ((hasE || hasNu) && (hasMu || hasLambda))
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "give the moduli either as %s/%s or as %s/%s, not both",
              optionName(prefix, "-E").c_str(), optionName(prefix, "-nu").c_str(), optionName(prefix, "-mu").c_str(),
              optionName(prefix, "-lambda").c_str());
    if (hasE || hasNu || (!base && !hasMu && !hasLambda)) {
      m->mu = energies::lameMu(E, nu);
      m->lambda = energies::lameLambda(E, nu);
    } else if (hasMu && !hasLambda && !base) {
      m->lambda = 0.0;
    }
  }
  PetscFunctionReturn(0);
}

// -mollifier_measure and -mollifier_eps, whose defaults depend on the run's start and the energy (fem_options.hpp:
// kDegenerateStartBand, kScaleFreeBand). A region inherits the global material's value where the user gave the global
// option (which the global material then read) and otherwise takes the default of its own case: under a degenerate
// start a fiber region in an iarap body gets the scale-free band, the body the paper's.
PetscErrorCode readMollifierBand(const char *prefix, ElementShape shape, const energies::Material *base,
                                 bool degenerateStart, energies::Material *m) {
  PetscBool globalMeasure = PETSC_FALSE, globalEps = PETSC_FALSE;
  PetscFunctionBeginUser;
  const bool baseRead = base && energies::energyContainsStretchInvariant(base->kind) &&
                        base->singularity.mode == energies::SingularityMode::Mollifier;
  if (baseRead) {  // already read (and marked used) by the global material
    PetscCall(PetscOptionsHasName(nullptr, nullptr, opt::mollifierMeasure.name, &globalMeasure));
    PetscCall(PetscOptionsHasName(nullptr, nullptr, opt::mollifierEps.name, &globalEps));
  }
  const bool startBand = degenerateStart && shape == ElementShape::Tet &&
                         energies::energyHasAnisotropicStretchTerms(m->kind);
  kernels::MollifierParams &band = m->singularity.mollifier;
  PetscCall(core::getChoice(opt::mollifierMeasure, &band.measure, nullptr,
                            {prefix, startBand ? opt::kDegenerateStartBand : nullptr, globalMeasure == PETSC_TRUE}));
  const bool scaleFree = band.measure == kernels::MollifierMeasure::ScaleFree;
  PetscCall(core::get(opt::mollifierEps, &band.eps, nullptr,
                      {prefix, scaleFree ? opt::kScaleFreeBand : nullptr, globalEps == PETSC_TRUE}));
  PetscFunctionReturn(0);
}

}  // namespace

PetscErrorCode materialUsesFibers(energies::EnergyKind kind, bool *uses) {
  PetscBool activation = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsHasName(nullptr, nullptr, "-activation", &activation));
  *uses = energies::energyUsesFibers(kind) || (kind == energies::EnergyKind::ShapeTarget && activation);
  PetscFunctionReturn(0);
}

PetscErrorCode readMaterialOptions(const char *prefix, ElementShape shape, const energies::Material *base,
                                   const UniformCellData *baseCell, bool degenerateStart,
                                   energies::Material *material, UniformCellData *cell) {
  energies::Material m = base ? *base : energies::Material{};
  UniformCellData c = baseCell ? *baseCell : UniformCellData{};
  const bool cloth = shape == ElementShape::Cloth;
  const int dim = shape == ElementShape::Tet ? 3 : 2;
  PetscBool set = PETSC_FALSE;
  PetscFunctionBeginUser;

  std::string name;
  const ReadContext at{prefix, cloth ? "cloth" : nullptr, base != nullptr};
  PetscCall(core::get(opt::energy, &name, &set, at));
  if (!name.empty()) {
    const auto kind = energies::energyFromName(name);
    if (!kind)
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s: unknown energy '%s' (known: %s)",
              optionName(prefix, "-energy").c_str(), name.c_str(), energies::energyNames().c_str());
    m.kind = *kind;
  }
  const char *ename = energies::energyName(m.kind);
  if (!energies::energySupportsShape(m.kind, shape)) {
    // A gmsh triangle mesh is read in 2D unless told otherwise: name the flag that makes it a cloth.
    const bool clothOnPlanar =
        shape == ElementShape::Planar && energies::energySupportsShape(m.kind, ElementShape::Cloth);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s: energy '%s' is not defined for %s elements%s",
            optionName(prefix, "-energy").c_str(), ename, energies::shapeName(shape),
            clothOnPlanar ? " (a cloth energy: it needs the triangle mesh in 3D, -dm_plex_gmsh_spacedim 3, without -uv_map)"
                          : "");
  }

  PetscCall(readModuli(prefix, cloth, base, &m));

  // The energy's own options (its descriptor's params, energies/catalog/).
  PetscCall(readEnergyParams(prefix, energies::energyInfo(m.kind), dim, base && base->kind == m.kind, &m, &c));

  // Fibers: the energies that read them per element, plus the basis of ortho / kim_aa.
  const bool basisEnergy = energies::energyInfo(m.kind).basis;
  bool usesFibers = false;
  PetscCall(materialUsesFibers(m.kind, &usesFibers));
  if (usesFibers || basisEnergy) {
    PetscBool setA = PETSC_FALSE, setB = PETSC_FALSE;
    PetscCall(readDirection(opt::fiber, at, shape, &c.a, &setA));
    c.fiberGiven = c.fiberGiven || setA;
    if (cloth || basisEnergy) PetscCall(readDirection(opt::fiber2, at, shape, &c.b, &setB));
    if (basisEnergy) {
      Eigen::Vector3d b = c.b;
      if (!setB && std::abs(c.a.dot(b)) > 0.9) b = (shape == ElementShape::Tet) ? c.a.unitOrthogonal() : Eigen::Vector3d(-c.a[1], c.a[0], 0.0);
      PetscCall(basisFrom(c.a, b, prefix, &m.basis));
    }
    if (m.kind == EnergyKind::Bw461 && std::abs(c.a.dot(c.b)) > 1e-8)
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
              "energy 'bw461' (Eq. 52) assumes orthogonal fibers but %s . %s = %g; use -energy bw46s for "
              "non-orthogonal fibers",
              optionName(prefix, "-fiber").c_str(), optionName(prefix, "-fiber2").c_str(), c.a.dot(c.b));
  }

  // Singularity mode.
  int mode = static_cast<int>(m.singularity.mode);
  PetscCall(core::getChoice(opt::singularity, &mode, &set, at));
  if (!energies::energyContainsStretchInvariant(m.kind)) {
    if (set)
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
              "option %s does not apply: energy '%s' has no I4/I6 term (only alx, iarap, ortho, aniso, fiber, "
              "bw461, bw46s, shape_target, caricature do)",
              optionName(prefix, "-singularity").c_str(), ename);
  } else {
    m.singularity.mode = *energies::singularityFromName(core::choices(opt::singularity)[mode]);
    if (m.singularity.mode == energies::SingularityMode::Mollifier) {
      PetscCall(readMollifierBand(prefix, shape, base, degenerateStart, &m));
      PetscCall(core::get(opt::mollifierProxy, &m.singularity.mollifier.proxy, nullptr, at));
    } else if (m.singularity.mode == energies::SingularityMode::Barrier) {
      PetscCall(core::get(opt::barrierEps, &m.singularity.barrier.eps, nullptr, at));
      PetscCall(core::get(opt::barrierStiffness, &m.singularity.barrierStiffness, nullptr, at));
    }
  }

  const std::string err = energies::finalizeMaterial(m, shape);
  if (!err.empty())
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "material%s%s: %s", prefix ? " " : "",
            prefix ? optionName(prefix, "").c_str() : "", err.c_str());
  *material = m;
  if (cell) *cell = c;
  PetscFunctionReturn(0);
}

}  // namespace aries::fem
