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
PetscErrorCode readMaterials(const Mesh &mesh, std::vector<MaterialOptions> *materials) {
  PetscFunctionBeginUser;
  MaterialOptions base;
  PetscCall(readMaterialOptions(nullptr, mesh.shape, nullptr, nullptr, &base.material, &base.cell));
  materials->push_back(base);
  std::vector<std::string> regionIds;
  PetscBool set = PETSC_FALSE;
  PetscCall(core::get(opt::regions, &regionIds, &set));
  for (const auto &rid : regionIds) {
    const std::string prefix = "region_" + rid + "_";
    MaterialOptions m;
    m.region = rid;
    PetscCall(readMaterialOptions(prefix.c_str(), mesh.shape, &base.material, &base.cell, &m.material, &m.cell));
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

// Every -load_traction_<set>, -load_force_<set> and -load_pressure_<set> given (the set is in the option's name, so the given options are
// listed to find them).
PetscErrorCode readLoads(int dim, bool tets, std::vector<SurfaceLoad> *loads) {
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
  for (const std::string &name : names) {
    SurfaceLoad load;
    const OptionDecl *decl = nullptr;
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
      if (!tets)
        SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
                "option %s: a follower pressure acts on the closed surfaces of a tet mesh, not on a planar or cloth mesh",
                name.c_str());
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

PetscErrorCode readFemOptions(const Mesh &mesh, FemOptions *o) {
  PetscBool set = PETSC_FALSE;
  PetscFunctionBeginUser;
  const bool planar = mesh.shape == energies::ElementShape::Planar;
  const bool cloth = mesh.shape == energies::ElementShape::Cloth;
  *o = FemOptions{};
  PetscCall(readMaterials(mesh, &o->materials));
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
  PetscCall(readLoads(planar ? 2 : 3, mesh.shape == energies::ElementShape::Tet, &o->loads));
  PetscFunctionReturn(0);
}

}  // namespace aries::fem
