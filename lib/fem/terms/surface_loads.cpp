#include "fem/terms/surface_loads.hpp"

#include "core/parallel.hpp"

#include <petscdmplex.h>

#include <cmath>

namespace aries::fem {

template <int R>
PetscErrorCode SurfaceLoads<R>::setup(const Mesh &mesh, const std::vector<SurfaceLoad> &loads) {
  MPI_Comm comm;
  PetscInt pStart, pEnd;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)mesh.dm, &comm));
  PetscCall(DMPlexGetChart(mesh.dm, &pStart, &pEnd));
  std::vector<char> copy;  // copies of another rank's points: a facet is counted by its owner only
  PetscCall(core::sharedLeafPoints(mesh.dm, &copy));
  for (const SurfaceLoad &load : loads) {
    if (load.kind == SurfaceLoad::Kind::Pressure) continue;  // terms/follower_pressure.hpp
    ++loads_;
    const bool totalForce = load.kind == SurfaceLoad::Kind::Force;
    const char *option = totalForce ? "-load_force_" : "-load_traction_";
    std::vector<PetscInt> facets;
    bool found = false;
    PetscCall(physicalGroupFacets(mesh, load.set, &facets, &found));
    // The rest area and the vertices of each owned facet.
    std::vector<std::vector<PetscInt>> facetVertices;
    std::vector<double> area;
    for (PetscInt f : facets) {
      if (copy[f - pStart]) continue;
      PetscInt nc, *closure = nullptr;
      std::vector<PetscInt> vs;
      PetscCall(DMPlexGetTransitiveClosure(mesh.dm, f, PETSC_TRUE, &nc, &closure));
      for (PetscInt k = 0; k < nc; ++k)
        if (closure[2 * k] >= mesh.vStart && closure[2 * k] < mesh.vEnd) vs.push_back(closure[2 * k] - mesh.vStart);
      PetscCall(DMPlexRestoreTransitiveClosure(mesh.dm, f, PETSC_TRUE, &nc, &closure));
      const Eigen::Vector3d &a = verts_[vs[0]].rest;
      double measure = 0.0;
      if (vs.size() == 3)
        measure = 0.5 * (verts_[vs[1]].rest - a).cross(verts_[vs[2]].rest - a).norm();
      else if (vs.size() == 2)
        measure = (verts_[vs[1]].rest - a).norm();
      facetVertices.push_back(vs);
      area.push_back(measure);
    }
    double local[2] = {0.0, static_cast<double>(area.size())}, total[2];
    for (double a : area) local[0] += a;
    PetscCallMPI(MPI_Allreduce(local, total, 2, MPI_DOUBLE, MPI_SUM, comm));
    if (!found || total[1] == 0.0) {
      std::string known;
      PetscCall(describePhysicalGroups(mesh, &known));
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
              "option %s%s: %s in mesh '%s' (a load acts on a boundary group: faces of a tet mesh, edges of a planar "
              "or cloth mesh; physical groups present: %s)",
              option, load.set.c_str(), found ? "the group has no boundary facets" : "no such physical group",
              mesh.filename.c_str(), known.c_str());
    }
    if (!(total[0] > 0.0))
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s%s: the group's rest area is zero", option,
              load.set.c_str());
    const Eigen::Vector3d traction = totalForce ? Eigen::Vector3d(load.value / total[0]) : load.value;
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
    if (vi.bcSet >= 0) continue;
    for (int i = 0; i < R; ++i) {
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
    if (vi.bcSet >= 0) continue;
    for (int i = 0; i < R; ++i) g[vi.loc + i] -= s_ * force_[3 * v + i];
  }
}

template class SurfaceLoads<2>;
template class SurfaceLoads<3>;

}  // namespace aries::fem
