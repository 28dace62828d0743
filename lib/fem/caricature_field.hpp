// Per-element data of the caricature energy (paper Sec. 6, Eq. 66: iarap + beta c I4(n)), computed from the rest
// mesh as the paper describes:
//  1. on the boundary surface of the tet mesh: vertex normals (area-weighted face normals, outward) and mean
//     curvature H from the cotangent Laplacian, Delta x = -2 H n (H = 1/r > 0 on a sphere), with barycentric areas;
//  2. the object's mean curvature H_mean = sum H A / sum A over the surface vertices (must be > 0: a closed surface);
//  3. H and n propagated to the interior vertices by the Laplace equation (P1 cotangent Laplacian of the tets,
//     surface values as Dirichlet data; PETSc KSP, options prefix caricature_, default CG + GAMG, rtol 1e-10);
//  4. per tet: c = -(mean of its 4 vertex H) / H_mean and n = the normalized mean of its 4 vertex normals.
// The sign of c: with Eq. 66 as printed, an element targets the stretch 1 - beta c / 2 along n (Eq. 65 with
// 2 (1 - lambda_1) = beta c). The paper says that for beta > 0 "regions with positive curvature expand, whereas those
// with negative curvature contract": that holds when c is negative on convex parts, i.e. the curvature convention
// Delta x = +2 H n. So c = -H_e / H_mean with H > 0 on convex parts; beta > 0 exaggerates (the surface's curvature
// variance grows), beta < 0 smooths.
#pragma once

#include "fem/cell_fields.hpp"
#include "mesh/mesh.hpp"

#include <Eigen/Dense>

#include <vector>

namespace aries::fem {

struct CaricatureField {
  std::vector<double> ratio;            // per local cell: c (negative on convex parts, see above)
  std::vector<Eigen::Vector3d> normal;  // per local cell: unit n
  double meanCurvature = 0.0;           // H_mean (1 / length)
  PetscInt surfaceVertices = 0;         // global count
  double minRatio = 0.0, maxRatio = 0.0;
  PetscInt degenerateNormals = 0;       // cells whose vertex normals cancel (c = 0 there), global count
};

// Collective. A mesh without a closed boundary surface of positive mean curvature is an error.
PetscErrorCode computeCaricatureField(const Mesh &mesh, CaricatureField *field);

// The caricature energy's per-cell field (energies::CellField::SurfaceCurvature): each cell's a = n and c from
// computeCaricatureField; tetrahedra only. The uniform -curvature, -fiber and -fiber_file are errors there.
template <int C>
std::unique_ptr<CellFieldSource<C>> makeCaricatureSource();

}  // namespace aries::fem
