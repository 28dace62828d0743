#include "fem/terms/surface_loads.hpp"

#include "core/parallel.hpp"

#include <cmath>

namespace aries::fem {

template <int R>
PetscErrorCode SurfaceLoads<R>::setup(const Mesh &mesh, const std::vector<SurfaceLoad> &loads) {
  MPI_Comm comm;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)mesh.dm, &comm));
  std::vector<char> copy;  // copies of another rank's points: a facet is counted by its owner only
  PetscCall(core::sharedLeafPoints(mesh.dm, &copy));
  for (const SurfaceLoad &load : loads) {
    if (load.kind == SurfaceLoad::Kind::Pressure) continue;  // terms/follower_pressure.hpp
    ++loads_;
    const bool totalForce = load.kind == SurfaceLoad::Kind::Force;
    const std::string option = (totalForce ? "-load_force_" : "-load_traction_") + load.set;
    std::vector<PetscInt> facets;
    PetscCall(ownedGroupFacets(mesh, copy, load.set, option,
                               "a load acts on a boundary group: faces of a tet mesh, edges of a planar or cloth mesh",
                               &facets));
    // The rest area and the vertices of each owned facet.
    std::vector<std::vector<PetscInt>> facetVertices(facets.size());
    std::vector<double> area(facets.size(), 0.0);
    double local = 0.0, total = 0.0;
    for (size_t k = 0; k < facets.size(); ++k) {
      std::vector<PetscInt> &vs = facetVertices[k];
      PetscCall(closureVertices(mesh, facets[k], &vs));
      const Eigen::Vector3d &a = verts_[vs[0]].rest;
      if (vs.size() == 3)
        area[k] = 0.5 * (verts_[vs[1]].rest - a).cross(verts_[vs[2]].rest - a).norm();
      else if (vs.size() == 2)
        area[k] = (verts_[vs[1]].rest - a).norm();
      local += area[k];
    }
    PetscCallMPI(MPI_Allreduce(&local, &total, 1, MPI_DOUBLE, MPI_SUM, comm));
    if (!(total > 0.0))
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s: the group's rest area is zero", option.c_str());
    const Eigen::Vector3d traction = totalForce ? Eigen::Vector3d(load.value / total) : load.value;
    for (size_t k = 0; k < facetVertices.size(); ++k) {
      const double share = area[k] / static_cast<double>(facetVertices[k].size());
      for (PetscInt v : facetVertices[k])
        for (int i = 0; i < 3; ++i) force_[3 * v + i] += share * traction[i];
    }
  }
  PetscFunctionReturn(0);
}

template <int R>
void SurfaceLoads<R>::addEnergy(const PetscScalar *x, double *energy, double *magnitude) const {
  double e = 0.0, mag = 0.0;
  for (size_t v = 0; v < verts_.size(); ++v) {
    const auto &vi = verts_[v];
    for (int i = 0; i < R; ++i) {
      if (vi.fixed(i)) continue;
      const double ei = s_ * force_[3 * v + i] * (x[vi.loc + i] - vi.rest[i]);
      e -= ei;
      mag += std::abs(ei);
    }
  }
  *energy += e;
  *magnitude += mag;
}

template <int R>
void SurfaceLoads<R>::addGradient(const PetscScalar *, PetscScalar *g) const {
  for (size_t v = 0; v < verts_.size(); ++v) {
    const auto &vi = verts_[v];
    for (int i = 0; i < R; ++i)
      if (!vi.fixed(i)) g[vi.loc + i] -= s_ * force_[3 * v + i];
  }
}

template class SurfaceLoads<2>;
template class SurfaceLoads<3>;

}  // namespace aries::fem
