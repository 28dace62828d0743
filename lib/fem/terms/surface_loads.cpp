#include "fem/terms/surface_loads.hpp"

#include "core/parallel.hpp"
#include "fem/terms/boundary_facets.hpp"
#include "kernels/enclosed_volume.hpp"

#include <cmath>

namespace aries::fem {

namespace {

// The rest area (length, for an edge) each vertex of a facet carries: area / 3 on a triangle, length / 2 on an edge;
// on a bilinear quadrangle (a hexahedron's face, vertices in cyclic closure order) the integral of each vertex's
// shape function over the possibly warped face, 2x2 Gauss points (exact for a parallelogram: area / 4 each).
// (A quadratic tetrahedral mesh's faces are 6-node triangles, possibly curved: SurfaceLoads::setup integrates them
// whole.) Returns the facet's rest area.
double facetVertexAreas(const std::vector<Eigen::Vector3d> &X, std::vector<double> *sharesOut) {
  const size_t n = X.size();
  std::vector<double> &share = *sharesOut;
  share.assign(n, 0.0);
  double area = 0.0;
  if (n == 2) {
    area = (X[1] - X[0]).norm();
    share.assign(2, area / 2.0);
  } else if (n == 3) {
    area = 0.5 * (X[1] - X[0]).cross(X[2] - X[0]).norm();
    share.assign(3, area / 3.0);
  } else if (n == 4) {
    const double g = 1.0 / std::sqrt(3.0), corner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (int q = 0; q < 4; ++q) {
      const double s = corner[q][0] * g, t = corner[q][1] * g;
      Eigen::Vector3d xs = Eigen::Vector3d::Zero(), xt = Eigen::Vector3d::Zero();
      double N[4];
      for (int v = 0; v < 4; ++v) {
        N[v] = (1 + corner[v][0] * s) * (1 + corner[v][1] * t) / 4.0;
        xs += corner[v][0] * (1 + corner[v][1] * t) / 4.0 * X[v];
        xt += corner[v][1] * (1 + corner[v][0] * s) / 4.0 * X[v];
      }
      const double dA = xs.cross(xt).norm();  // Gauss weight 1
      for (int v = 0; v < 4; ++v) share[v] += N[v] * dA;
      area += dA;
    }
  }
  return area;
}

}  // namespace

template <int R>
PetscErrorCode SurfaceLoads<R>::setup(const Mesh &mesh, const std::vector<SurfaceLoad> &loads) {
  MPI_Comm comm;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)mesh.dm, &comm));
  std::vector<char> copy;  // copies of another rank's points: a facet is counted by its owner only
  PetscCall(core::sharedLeafPoints(mesh.dm, &copy));
  for (const SurfaceLoad &load : loads) {
    const bool pressure = load.kind == SurfaceLoad::Kind::Pressure;
    if (pressure && !load.dead) continue;  // terms/follower_pressure.hpp
    ++loads_;
    const bool totalForce = load.kind == SurfaceLoad::Kind::Force;
    const std::string option =
        (pressure ? "-load_pressure_" : totalForce ? "-load_force_" : "-load_traction_") + load.set;
    std::vector<PetscInt> facets;
    PetscCall(ownedGroupFacets(mesh, copy, load.set, option,
                               pressure ? "a dead pressure acts on a boundary group: faces of a volume mesh, edges of a "
                                          "planar mesh"
                                        : "a load acts on a boundary group: faces of a tet or hexahedral mesh, edges "
                                          "of a planar or cloth mesh",
                               &facets));
    // A pressure needs each facet's outward normal (the cell it bounds); a traction only its vertices.
    std::vector<OrientedFacet> oriented;
    if (pressure) PetscCall(orientBoundaryFacets(mesh, verts_, facets, option, &oriented));
    // The vertices of each owned facet and the rest area each of them carries (integral of its shape function); for
    // a pressure the area vector each carries, int N_v n dA.
    std::vector<std::vector<PetscInt>> facetVertices;
    std::vector<std::vector<double>> shares;
    std::vector<std::vector<Eigen::Vector3d>> moments;
    double local = 0.0, total = 0.0;
    if (mesh.quadratic) {  // whole 6-node faces (curved where the mesh's edge nodes are): the refined DM's 4 per face
      std::vector<std::array<PetscInt, 6>> faces;
      PetscCall(quadraticGroupFaces(mesh, verts_, facets, option, &faces));
      for (const auto &f : faces) {
        kernels::Mat<6, 3> X;
        for (int v = 0; v < 6; ++v) X.row(v) = verts_[f[v]].rest.transpose();
        const kernels::Vec<6> a = kernels::faceAreaShares<kernels::face::Tri6>(X);
        const kernels::Mat<6, 3> m = kernels::faceAreaMoments<kernels::face::Tri6>(X);
        facetVertices.emplace_back(f.begin(), f.end());
        shares.emplace_back(a.data(), a.data() + 6);
        moments.emplace_back();
        for (int v = 0; v < 6; ++v) moments.back().push_back(m.row(v).transpose());
        local += a.sum();
      }
    } else {  // each facet as it is
      facetVertices.resize(facets.size());
      shares.resize(facets.size());
      moments.resize(facets.size());
      for (size_t k = 0; k < facets.size(); ++k) {
        std::vector<PetscInt> &vs = facetVertices[k];
        if (pressure) vs.assign(oriented[k].vertex.begin(), oriented[k].vertex.begin() + oriented[k].count);
        else PetscCall(closureVertices(mesh, facets[k], &vs));
        std::vector<Eigen::Vector3d> X;
        for (PetscInt v : vs) X.push_back(verts_[v].rest);
        local += facetVertexAreas(X, &shares[k]);
        if (!pressure) continue;
        if (vs.size() == 4) {  // a possibly warped bilinear quadrangle: its normal varies over it
          kernels::Mat<4, 3> Xq;
          for (int v = 0; v < 4; ++v) Xq.row(v) = X[v].transpose();
          const kernels::Mat<4, 3> m = kernels::faceAreaMoments<kernels::face::Quad4>(Xq);
          for (int v = 0; v < 4; ++v) moments[k].push_back(m.row(v).transpose());
        } else {  // flat: its unit normal times each vertex's share of the area
          const Eigen::Vector3d n = restAreaVector(verts_, oriented[k]).normalized();
          for (double a : shares[k]) moments[k].push_back(a * n);
        }
      }
    }
    PetscCallMPI(MPI_Allreduce(&local, &total, 1, MPI_DOUBLE, MPI_SUM, comm));
    if (!(total > 0.0))
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s: the group's rest area is zero", option.c_str());
    const Eigen::Vector3d traction = totalForce ? Eigen::Vector3d(load.value / total) : load.value;
    for (size_t k = 0; k < facetVertices.size(); ++k)
      for (size_t j = 0; j < facetVertices[k].size(); ++j)
        for (int i = 0; i < 3; ++i)
          force_[3 * facetVertices[k][j] + i] +=
              pressure ? -load.value[0] * moments[k][j][i] : shares[k][j] * traction[i];
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
