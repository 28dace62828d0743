// Material from PETSc options (documented in docs/options.md). Only the options the chosen energy uses are read,
// so a stray option (e.g. -gamma with iarap) stays unused and -options_left reports it.
#pragma once

#include "energies/material.hpp"

#include <petscsys.h>

namespace aries::fem {

// Element data that options can set uniformly (the FE layer may override per cell from files).
struct UniformCellData {
  Eigen::Vector3d a = Eigen::Vector3d::UnitX();  // -fiber
  Eigen::Vector3d b = Eigen::Vector3d::UnitY();  // -fiber2
  Eigen::Matrix3d target = Eigen::Matrix3d::Identity();  // -target (shape_target)
  double curvature = 1.0;                                 // -curvature (caricature)
  bool fiberGiven = false;
};

// Reads the material under `prefix` (nullptr for the global one, "region_<id>_" for a region), starting from
// `base` where given, for elements of `shape`; validates and finalizes it. Errors are PETSC_ERR_USER_INPUT with
// the option name in the message.
PetscErrorCode readMaterialOptions(const char *prefix, energies::ElementShape shape, const energies::Material *base,
                                   const UniformCellData *baseCell, energies::Material *material,
                                   UniformCellData *cell);

// Whether elements of this energy read fibers (-fiber, -fiber_file): the fiber energies, and shape_target when the
// targets come from -activation (along each element's fiber).
PetscErrorCode materialUsesFibers(energies::EnergyKind kind, bool *uses);

template <int C>
energies::CellData<C> toCellData(const UniformCellData &u) {
  energies::CellData<C> c;
  c.a = u.a.head<C>();
  c.b = u.b.head<C>();
  c.target = u.target.topLeftCorner<C, C>();
  c.curvature = u.curvature;
  return c;
}

}  // namespace aries::fem
