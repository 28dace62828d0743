#include "fem/discretization_options.hpp"

#include "core/options.hpp"
#include "fem/fem_options.hpp"
#include "fem/material_options.hpp"

namespace aries::fem {

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
  PetscFunctionReturn(0);
}

}  // namespace aries::fem
