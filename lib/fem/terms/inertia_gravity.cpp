#include "fem/terms/inertia_gravity.hpp"

#include <cmath>

namespace aries::fem {

template <int R>
void InertiaGravity<R>::addEnergy(const PetscScalar *x, double *energy, double *magnitude) const {
  const bool inertia = dt_ > 0.0, grav = gravity_.squaredNorm() > 0.0;
  double e = 0.0, mag = 0.0;
  if (inertia || grav)
    for (size_t v = 0; v < verts_.size(); ++v) {
      const auto &vi = verts_[v];
      if (!vi.ownedFree()) continue;
      for (int i = 0; i < R; ++i) {
        if (vi.fixed(i)) continue;
        const double xi = x[vi.loc + i];
        if (inertia) {
          const double d = xi - xTilde_[vi.loc + i];
          const double ei = 0.5 * mass_[v] * d * d / (dt_ * dt_);
          e += ei;
          mag += ei;
        }
        if (grav) {  // relative to the rest position: neither the value nor its round-off depends on the origin
          const double ei = gravityMass_[v] * gravity_[i] * (xi - vi.rest[i]);
          e -= ei;
          mag += std::abs(ei);
        }
      }
    }
  *energy += e;
  *magnitude += mag;
}

template <int R>
void InertiaGravity<R>::addGradient(const PetscScalar *x, PetscScalar *g) const {
  const bool inertia = dt_ > 0.0, grav = gravity_.squaredNorm() > 0.0;
  if (!inertia && !grav) return;
  for (size_t v = 0; v < verts_.size(); ++v) {
    const auto &vi = verts_[v];
    if (!vi.ownedFree()) continue;
    for (int i = 0; i < R; ++i) {
      if (vi.fixed(i)) continue;
      if (inertia) g[vi.loc + i] += mass_[v] * (x[vi.loc + i] - xTilde_[vi.loc + i]) / (dt_ * dt_);
      if (grav) g[vi.loc + i] -= gravityMass_[v] * gravity_[i];
    }
  }
}

template <int R>
PetscErrorCode InertiaGravity<R>::addHessian(const PetscScalar *, const HessianAssembly &how, Mat J) const {
  PetscFunctionBeginUser;
  if (!(dt_ > 0.0)) PetscFunctionReturn(0);  // gravity is linear
  for (size_t v = 0; v < verts_.size(); ++v) {
    const auto &vi = verts_[v];
    if (!vi.ownedFree()) continue;
    for (int i = 0; i < R; ++i) {
      const PetscInt row = vi.row(i);
      if (row < 0) continue;
      const PetscScalar m = mass_[v] / (dt_ * dt_);
      if (how.product()) how.productOut[vi.loc + i] += m * how.productIn[vi.loc + i];  // diagonal: free dofs only
      else PetscCall(MatSetValues(J, 1, &row, 1, &row, &m, ADD_VALUES));
    }
  }
  PetscFunctionReturn(0);
}

template <int R>
void InertiaGravity<R>::addCurvature(const PetscScalar *, const PetscScalar *const d[], int K, GramMatrix *q) const {
  if (!(dt_ > 0.0)) return;
  for (size_t v = 0; v < verts_.size(); ++v) {
    const auto &vi = verts_[v];
    if (!vi.ownedFree()) continue;
    const double m = mass_[v] / (dt_ * dt_);
    for (int i = 0; i < R; ++i)
      if (!vi.fixed(i))
        for (int k = 0; k < K; ++k)
          for (int l = 0; l < K; ++l) (*q)(k, l) += m * d[k][vi.loc + i] * d[l][vi.loc + i];
  }
}

template class InertiaGravity<2>;
template class InertiaGravity<3>;

}  // namespace aries::fem
