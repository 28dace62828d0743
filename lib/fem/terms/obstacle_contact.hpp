// Contact with analytic obstacles (-obstacle_plane, -obstacle_sphere; 3D meshes): a smooth log barrier
// (kernels/obstacle_barrier.hpp) on the distance of every owned free vertex to every obstacle, active below
// -contact_dhat, with stiffness -contact_stiffness.
#pragma once

#include "mesh/mesh.hpp"
#include "fem/terms/term.hpp"
#include "fem/vertex_layout.hpp"
#include "kernels/obstacle_barrier.hpp"

#include <vector>

namespace aries::fem {

// -obstacle_plane, -obstacle_sphere, -contact_dhat, -contact_stiffness.
struct ObstacleOptions {
  std::vector<kernels::Obstacle> obstacles;
  double dhat = 0.0;            // barrier width (default 1e-2 L)
  double stiffness = 0.0;       // barrier stiffness when given ...
  bool stiffnessGiven = false;  // ... else the body's own at a vertex (ObstacleContact::setup)
};

// Reads the obstacle options (-contact_* only with an obstacle); a malformed one is a one-line error.
PetscErrorCode readObstacleOptions(const Mesh &mesh, ObstacleOptions *o);

class ObstacleContact final : public Term {
 public:
  explicit ObstacleContact(const VertexTable &verts) : verts_(verts) {}
  // `defaultStiffness` is the body's own stiffness at a vertex. Fails with a one-line error if a rest vertex is
  // inside an obstacle. Collective.
  PetscErrorCode setup(const Mesh &mesh, const ObstacleOptions &o, double defaultStiffness);
  bool empty() const { return obstacles_.empty(); }
  const char *name() const override { return "obstacle contact"; }
  void addEnergy(const PetscScalar *x, double *energy, double *magnitude) const override;
  void addGradient(const PetscScalar *x, PetscScalar *g) const override;
  PetscErrorCode addHessian(const PetscScalar *x, const HessianAssembly &how, Mat J) const override;
  void addCurvature(const PetscScalar *x, const PetscScalar *const d[], int K, GramMatrix *q) const override;

 private:
  kernels::Derivs<3> at(const Eigen::Vector3d &xv, const kernels::Obstacle &o, kernels::Order order) const {
    return kernels::obstacleBarrier(o, xv, dhat_, kappa_, order);
  }
  const VertexTable &verts_;
  std::vector<kernels::Obstacle> obstacles_;
  double dhat_ = 0.0, kappa_ = 0.0;
};

}  // namespace aries::fem
