// Cloth bending (-bending k): the quadratic bending energy of every interior edge of a surface mesh in 3D
// (kernels/quadratic_bending.hpp), one hinge per edge owned by this rank: the edge (v0, v1) and the two vertices
// opposite it (v2, v3). Its couplings are preallocated as every term's are (Discretization::preallocateHessian).
#pragma once

#include "fem/terms/term.hpp"
#include "fem/vertex_layout.hpp"
#include "kernels/quadratic_bending.hpp"

#include <petscdm.h>

#include <array>
#include <functional>
#include <vector>

namespace aries::fem {

class BendingHinges final : public Term {
 public:
  struct Hinge {
    std::array<PetscInt, 4> vertex;  // local vertex indices
    kernels::BendingHinge rest;
  };
  BendingHinges(const VertexTable &verts, double stiffness) : verts_(verts), stiffness_(stiffness) {}
  // One hinge per interior edge this rank owns; `opposite(cell, v0, v1)` returns the vertex of a triangle (a point
  // of the DM's cell stratum) that is not on the edge.
  PetscErrorCode build(DM dm, PetscInt vStart, const std::function<PetscInt(PetscInt, PetscInt, PetscInt)> &opposite);
  const char *name() const override { return "bending hinges"; }
  double stiffness() const { return stiffness_; }
  void addEnergy(const PetscScalar *x, double *energy, double *magnitude) const override;
  void addGradient(const PetscScalar *x, PetscScalar *g) const override;
  PetscErrorCode addHessian(const PetscScalar *x, const HessianAssembly &how, Mat J) const override;
  void addCurvature(const PetscScalar *x, const PetscScalar *const d[], int K, GramMatrix *q) const override;
  PetscInt offRankHessianValues() const override;

 private:
  void positions(const Hinge &h, const PetscScalar *x, Eigen::Vector3d xs[4]) const {
    for (int i = 0; i < 4; ++i) xs[i] = Eigen::Map<const Eigen::Vector3d>(x + verts_[h.vertex[i]].loc);
  }
  const VertexTable &verts_;
  double stiffness_;
  std::vector<Hinge> hinges_;
};

}  // namespace aries::fem
