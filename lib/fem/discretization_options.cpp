#include "fem/discretization_options.hpp"

#include "core/options.hpp"
#include "fem/fem_options.hpp"
#include "fem/material_options.hpp"

#include <algorithm>
#include <sstream>

namespace aries::fem {

using core::OptionDecl;

namespace {

// The global material, then one per -regions entry (starting from the global one: prefix region_<id>_).
PetscErrorCode readMaterials(const Mesh &mesh, bool degenerateStart, std::vector<MaterialOptions> *materials) {
  PetscFunctionBeginUser;
  MaterialOptions base;
  PetscCall(readMaterialOptions(nullptr, mesh.shape, nullptr, nullptr, degenerateStart, &base.material,
                                &base.cell));
  materials->push_back(base);
  std::vector<std::string> regionIds;
  PetscBool set = PETSC_FALSE;
  PetscCall(core::get(opt::regions, &regionIds, &set));
  for (const auto &rid : regionIds) {
    const std::string prefix = "region_" + rid + "_";
    MaterialOptions m;
    m.region = rid;
    PetscCall(readMaterialOptions(prefix.c_str(), mesh.shape, &base.material, &base.cell, degenerateStart,
                                  &m.material, &m.cell));
    materials->push_back(m);
  }
  PetscFunctionReturn(0);
}

PetscErrorCode readDynamics(int dim, DynamicsTerms *dyn) {
  PetscBool set = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCall(core::get(opt::density, &dyn->density, &set));
  std::vector<PetscReal> g;
  PetscCall(core::get(opt::gravity, &g, &set));
  if (dim == 3 && g.size() != 3)
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -gravity takes 3 comma-separated numbers on a 3D mesh, got %d",
            (int)g.size());
  if (dim == 2 && g.size() == 3 && g[2] != 0.0)
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -gravity: a 2D mesh takes gx,gy (z must be 0)");
  for (size_t k = 0; k < g.size() && k < static_cast<size_t>(dim); ++k) dyn->gravity[k] = g[k];
  PetscFunctionReturn(0);
}

// Every -load_traction_<set>, -load_force_<set> and -load_pressure_<set> given (the set is in the option's name, so the
// given options are listed to find them), and each pressure's -load_pressure_<set>_kind. `volume`: a tet or hexahedral
// mesh; `planar`: a 2D mesh (a cloth mesh carries no pressure).
PetscErrorCode readLoads(int dim, bool volume, bool planar, std::vector<SurfaceLoad> *loads) {
  char *all = nullptr;
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetAll(nullptr, &all));
  std::istringstream in(all ? all : "");
  std::string token;
  std::vector<std::string> names;
  while (in >> token)
    if (token.rfind("-load_", 0) == 0 && std::find(names.begin(), names.end(), token) == names.end())
      names.push_back(token);
  PetscCall(PetscFree(all));
  const std::string pressureFamily = "-load_pressure_", kindSuffix = "_kind";
  auto isKindOption = [&](const std::string &name) {
    return name.rfind(pressureFamily, 0) == 0 && name.size() > pressureFamily.size() + kindSuffix.size() &&
           name.compare(name.size() - kindSuffix.size(), kindSuffix.size(), kindSuffix) == 0;
  };
  for (const std::string &name : names) {
    SurfaceLoad load;
    const OptionDecl *decl = nullptr;
    if (isKindOption(name)) {  // read with its pressure below; a kind without a pressure is an error
      const std::string pressure = name.substr(0, name.size() - kindSuffix.size());
      if (std::find(names.begin(), names.end(), pressure) == names.end())
        SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
                "option %s: no pressure %s is given (a set's pressure kind needs its pressure; a set name cannot end "
                "in _kind)",
                name.c_str(), pressure.c_str());
      continue;
    }
    const std::pair<const char *, SurfaceLoad::Kind> families[] = {{"-load_traction_", SurfaceLoad::Kind::Traction},
                                                                   {"-load_force_", SurfaceLoad::Kind::Force},
                                                                   {"-load_pressure_", SurfaceLoad::Kind::Pressure}};
    for (const auto &[family, kind] : families)
      if (name.rfind(family, 0) == 0) {
        load.set = name.substr(std::string(family).size());
        load.kind = kind;
        decl = kind == SurfaceLoad::Kind::Traction ? &opt::loadTraction
               : kind == SurfaceLoad::Kind::Force  ? &opt::loadForce
                                                   : &opt::loadPressure;
      }
    if (!decl) continue;  // not a load option: left to the unused-option check
    if (load.set.empty())
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s names no boundary group (e.g. %stop)", name.c_str(),
              name.c_str());
    const std::string prefix = name.substr(1);
    if (load.kind == SurfaceLoad::Kind::Pressure) {
      const std::string kindPrefix = prefix + "_";
      int kind = 0;
      PetscCall(core::getChoice(opt::loadPressureKind, &kind, nullptr, {kindPrefix.c_str()}));
      load.dead = core::choices(opt::loadPressureKind)[kind] == std::string("dead");
      if (!volume && !planar)
        SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
                "option %s: a pressure acts on the faces of a volume mesh or the edges of a planar mesh, not on a "
                "cloth mesh (use -load_traction_%s for a dead load)",
                name.c_str(), load.set.c_str());
      if (!volume && !load.dead)
        SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
                "option %s: a follower pressure acts on the closed surfaces of a volume mesh; on a planar mesh "
                "-load_pressure_%s_kind dead gives the dead pressure",
                name.c_str(), load.set.c_str());
      PetscCall(core::get(*decl, &load.value[0], nullptr, {prefix.c_str()}));
      loads->push_back(load);
      continue;
    }
    std::vector<PetscReal> v;
    PetscCall(core::get(*decl, &v, nullptr, {prefix.c_str()}));
    if (dim == 3 && v.size() != 3)
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s takes 3 comma-separated numbers on a 3D mesh, got %d",
              name.c_str(), (int)v.size());
    if (dim == 2 && v.size() == 3 && v[2] != 0.0)
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s: a 2D mesh takes x,y (z must be 0)", name.c_str());
    for (size_t k = 0; k < v.size(); ++k) load.value[k] = v[k];
    loads->push_back(load);
  }
  PetscFunctionReturn(0);
}

}  // namespace

PetscErrorCode readFemOptions(const Mesh &mesh, bool degenerateStart, FemOptions *o) {
  PetscBool set = PETSC_FALSE;
  PetscFunctionBeginUser;
  const bool planar = mesh.shape == energies::ElementShape::Planar;
  const bool cloth = mesh.shape == energies::ElementShape::Cloth;
  *o = FemOptions{};
  PetscCall(readMaterials(mesh, degenerateStart, &o->materials));
  PetscCall(readDynamics(planar ? 2 : 3, &o->dynamics));
  PetscCall(readBoundaryOptions(&o->boundary));
  bool anyFibers = false;
  for (const auto &m : o->materials) {
    bool uses = false;
    PetscCall(materialUsesFibers(m.material.kind, &uses));
    anyFibers = anyFibers || uses;
  }
  if (anyFibers) {
    PetscCall(core::get(opt::fiberFile, &o->fiberFile, &set));
    if (cloth) PetscCall(core::get(opt::fiber2File, &o->fiber2File, &set));
  }
  if (planar) {
    PetscBool keep = PETSC_FALSE;
    PetscCall(core::get(opt::keepOrientation, &keep, nullptr, {nullptr, mesh.uvMap ? "uv_map" : nullptr}));
    o->keepOrientation = keep;
  }
  if (cloth) PetscCall(core::get(opt::bending, &o->bending, &set));
  if (!planar) PetscCall(readObstacleOptions(mesh, &o->contact));
  PetscCall(readLoads(planar ? 2 : 3, mesh.shape == energies::ElementShape::Tet, planar, &o->loads));
  PetscFunctionReturn(0);
}

}  // namespace aries::fem
