// Material from PETSc options (documented in docs/options.md). Only the options the chosen energy uses are read,
// so a stray option (e.g. -gamma with iarap) stays unused and -options_left reports it.
#pragma once

#include "energies/material.hpp"

#include <petscsys.h>

namespace aries::fem {

using energies::UniformCellData;

// Reads the material under `prefix` (nullptr for the global one, "region_<id>_" for a region), starting from
// `base` where given, for elements of `shape`; validates and finalizes it. `degenerateStart`: the run starts
// from a scramble, invert or collapse state, static or backward Euler (it selects the mollifier band's defaults,
// fem_options.hpp). Errors are PETSC_ERR_USER_INPUT with the option name in the message.
PetscErrorCode readMaterialOptions(const char *prefix, energies::ElementShape shape, const energies::Material *base,
                                   const UniformCellData *baseCell, bool degenerateStart,
                                   energies::Material *material, UniformCellData *cell);

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
