// Inertia and gravity on the owned free vertices (lumped mass m_v, backward Euler as an incremental potential):
// sum_v m_v [ |x_v - x~_v|^2 / (2 dt^2) - g . (x_v - X_v) ], with dt and the prediction x~ of the step being solved
// for (fem/step_state.hpp) and the rest position X_v as the gravity potential's datum (a constant shift that keeps
// the value and its round-off scale independent of the coordinate origin); static solves have dt = 0 and keep only
// gravity.
#pragma once

#include "fem/terms/term.hpp"
#include "fem/vertex_layout.hpp"

#include <vector>

namespace aries::fem {

template <int R>
class InertiaGravity final : public Term {
 public:
  // `mass`: the lumped mass (inertia); `gravityMass`: the consistent load int rho N_v that gravity acts on (the same
  // numbers except on quadratic tetrahedra, whose lumped mass is HRZ's). `localSize`: the length of a local vector;
  // the prediction starts at 0.
  InertiaGravity(const VertexTable &verts, const std::vector<double> &mass, const std::vector<double> &gravityMass,
                 const Eigen::Vector3d &gravity, PetscInt localSize)
      : verts_(verts), mass_(mass), gravityMass_(gravityMass), gravity_(gravity), xTilde_(localSize, 0.0) {}
  void setTimeStep(double dt) { dt_ = dt; }
  std::vector<double> &prediction() { return xTilde_; }  // local vector layout
  const char *name() const override { return "inertia and gravity"; }
  void addEnergy(const PetscScalar *x, double *energy, double *magnitude) const override;
  void addGradient(const PetscScalar *x, PetscScalar *g) const override;
  PetscErrorCode addHessian(const PetscScalar *x, const HessianAssembly &how, Mat J) const override;
  void addCurvature(const PetscScalar *x, const PetscScalar *const d[], int K, GramMatrix *q) const override;

 private:
  const VertexTable &verts_;
  const std::vector<double> &mass_;         // per local vertex
  const std::vector<double> &gravityMass_;  // per local vertex
  const Eigen::Vector3d &gravity_;
  double dt_ = 0.0;
  std::vector<double> xTilde_;       // per local dof
};

}  // namespace aries::fem
