// Dead surface loads on boundary groups (-load_traction_<set>, -load_force_<set>, -load_pressure_<set> with
// -load_pressure_<set>_kind dead), ramped with the load parameter s: each facet (a face of a volume mesh, an edge of a
// planar or cloth mesh) carries the traction t (force per rest area; a total force F is the traction F / area of its
// set) and gives each of its vertices the consistent nodal force t int N_v dA (t area / n on a linear facet, n its
// vertices). A dead pressure p is the traction -p n along the rest facet's outward normal n: each vertex gets
// -p int N_v n dA (kernels::faceAreaMoments on a warped quadrangle), on any set, open or closed. The potential is
// -s sum_v f_v . (x_v - X_v) over the free vertices (a supported vertex's share goes into its support; the rest
// position X_v is the datum, so neither the value nor its round-off depends on the origin). Linear: no Hessian.
#pragma once

#include "fem/discretization_options.hpp"
#include "mesh/mesh.hpp"
#include "fem/terms/term.hpp"
#include "fem/vertex_layout.hpp"

#include <vector>

namespace aries::fem {

template <int R>
class SurfaceLoads final : public Term {
 public:
  explicit SurfaceLoads(const VertexTable &verts) : verts_(verts), force_(3 * verts.size(), 0.0) {}
  // The nodal forces of every load on this rank's facets (each facet counted on the rank that owns it). A set not in
  // the mesh, or without facets, is a one-line error naming the groups present. Collective.
  PetscErrorCode setup(const Mesh &mesh, const std::vector<SurfaceLoad> &loads);
  bool empty() const { return loads_ == 0; }
  void setLoad(double s) { s_ = s; }
  const char *name() const override { return "surface loads"; }
  void addEnergy(const PetscScalar *x, double *energy, double *magnitude) const override;
  void addGradient(const PetscScalar *x, PetscScalar *g) const override;
  PetscErrorCode addHessian(const PetscScalar *, const HessianAssembly &, Mat) const override { return 0; }
  void addCurvature(const PetscScalar *, const PetscScalar *const[], int, GramMatrix *) const override {}

 private:
  const VertexTable &verts_;
  std::vector<double> force_;  // per local vertex (3): this rank's facets' shares at load 1
  size_t loads_ = 0;
  double s_ = 0.0;
};

}  // namespace aries::fem
