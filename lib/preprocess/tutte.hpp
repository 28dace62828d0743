// Tutte embedding of a disk-topology triangle surface (the initial map of the UV parameterization, paper Fig. 14):
// the boundary loop is placed on a circle by arc length (radius = loop length / 2 pi, so the map has the surface's
// scale), every interior vertex at the average of its neighbours (positive, convex edge weights: the embedding has
// no flipped triangle), solved in parallel with PETSc KSP (options prefix tutte_, default CG + GAMG, rtol 1e-10).
#pragma once

#include "mesh/mesh.hpp"

namespace aries::fem {

// (u, v) for every local vertex (index v - vStart). Collective. A surface that is not a disk (no or several
// boundary loops, or a branching boundary) is an error.
PetscErrorCode tutteEmbedding(const Mesh &mesh, std::vector<Eigen::Vector2d> *uv);

}  // namespace aries::fem
