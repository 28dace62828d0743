// One coarse level of the nested iteration (nested_start.cpp): a coarse mesh of the same body with its own
// discretization (the same options) and its own simulation (state, velocities, Newton solver, and its own coarser
// level), and the interpolations between it and the next finer level. Internal to lib/solver.
#pragma once

#include "fem/discretization.hpp"
#include "mesh/mesh_transfer.hpp"
#include "solver/simulation.hpp"

#include <memory>

namespace aries::solver {

struct CoarseLevel {
  fem::Mesh mesh;                              // members in this order: destroyed simulation first, mesh last
  std::unique_ptr<fem::Discretization> disc;
  Simulation sim;
  fem::VertexInterpolation toFine;    // the coarse mesh's fields at the finer mesh's vertices
  fem::VertexInterpolation fromFine;  // the finer mesh's fields at the coarse mesh's vertices
};

}  // namespace aries::solver
