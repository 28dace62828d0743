// Discrete harmonic extension on a simplicial mesh: given values at constrained vertices, solve
//   sum_j K_ij u_j = 0   at every free vertex i,   u_i = g_i at every constrained vertex,
// with K assembled from per-cell stiffness matrices (graph Laplacian for the Tutte embedding, the P1 cotangent
// Laplacian for the caricature fields). Several fields share one matrix and one KSP (options prefix `prefix`,
// default CG + GAMG, rtol 1e-10).
#pragma once

#include "mesh/mesh.hpp"

#include <functional>
#include <vector>

namespace aries::fem {

struct HarmonicProblem {
  int verticesPerCell = 3;
  // Ke (verticesPerCell^2, row-major) of local cell c with local vertices `verts` (v - vStart, closure order).
  std::function<void(PetscInt c, const PetscInt *verts, double *Ke)> cellStiffness;
  std::vector<char> constrained;     // per local vertex (v - vStart); must agree on every rank holding the vertex
  int components = 1;
  std::vector<double> values;        // per local vertex x components: g at constrained vertices (others ignored)
  std::string prefix = "harmonic_";  // KSP options prefix
  std::string what = "harmonic extension";  // for the error message if the solve fails
};

// Fills `values` at the free vertices (all local vertices, ghosts included). Collective.
PetscErrorCode harmonicExtension(const Mesh &mesh, HarmonicProblem *problem);

}  // namespace aries::fem
