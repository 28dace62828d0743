// Follower pressure on closed boundary surfaces (-load_pressure_<set> p, tet meshes), ramped with the load parameter
// s: the pressure p acts on the deformed surface against its outward normal (the body's), so p > 0 on the outer
// surface squeezes the body and p > 0 on a cavity's wall inflates the cavity. On a closed surface it is conservative:
// its potential is s p (V(x) - V(X)), V the volume the surface encloses with the body's outward orientation
// (kernels/enclosed_volume.hpp; a cavity's wall encloses minus the cavity's volume), so Newton minimizes one total
// potential and its Hessian is symmetric. That Hessian is indefinite (trace-free per triangle): each triangle's
// 9x9 block goes through the same eigenvalue filter as the elements (-psd_projection) so CG sees a PSD system; the
// subspace step and the adaptive filter use the true one. An open set has no potential (its load is not
// conservative) and is an error.
#pragma once

#include "fem/discretization_options.hpp"
#include "fem/mesh.hpp"
#include "fem/terms/term.hpp"
#include "fem/vertex_layout.hpp"

#include <array>
#include <vector>

namespace aries::fem {

class FollowerPressure final : public Term {
 public:
  explicit FollowerPressure(const VertexTable &verts) : verts_(verts) {}
  // The triangles of every pressure load owned by this rank, ordered with the body's outward normal. A set not in
  // the mesh, without boundary faces, or not closed is a one-line error. Collective.
  PetscErrorCode setup(const Mesh &mesh, const std::vector<SurfaceLoad> &loads);
  bool empty() const { return loads_ == 0; }
  void setLoad(double s) { s_ = s; }
  const char *name() const override { return "follower pressure"; }
  void addEnergy(const PetscScalar *x, double *energy, double *magnitude) const override;
  void addGradient(const PetscScalar *x, PetscScalar *g) const override;
  PetscErrorCode addHessian(const PetscScalar *x, const HessianAssembly &how, Mat J) const override;
  void addCurvature(const PetscScalar *x, const PetscScalar *const d[], int K, GramMatrix *q) const override;
  PetscInt offRankHessianValues() const override;

 private:
  struct Triangle {
    std::array<PetscInt, 3> vertex;  // local vertex indices, outward order
    int set;                         // index of its load
  };
  Eigen::Vector3d position(PetscInt v, const PetscScalar *x) const;
  const VertexTable &verts_;
  std::vector<Triangle> triangles_;
  std::vector<double> pressure_;         // per load: p at load 1
  std::vector<Eigen::Vector3d> center_;  // per load: the set's rest centroid (the pieces' reference point)
  std::vector<double> restVolume_;       // per load: this rank's share of V(X) (the potential's datum)
  size_t loads_ = 0;
  double s_ = 0.0;
};

}  // namespace aries::fem
