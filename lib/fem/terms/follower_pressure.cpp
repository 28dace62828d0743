#include "fem/terms/follower_pressure.hpp"

#include "core/parallel.hpp"
#include "kernels/enclosed_volume.hpp"
#include "kernels/psd_projection.hpp"

#include <petscdmplex.h>
#include <petscsf.h>

#include <algorithm>
#include <cmath>

namespace aries::fem {

namespace {

// Edges of the set's triangles that do not have exactly two of them, over all ranks (0: a closed surface).
PetscErrorCode openEdges(DM dm, const std::vector<PetscInt> &faces, PetscInt pStart, PetscInt pEnd,
                         const std::vector<char> &copy, PetscInt *open) {
  PetscSF sf;
  PetscFunctionBeginUser;
  std::vector<PetscInt> count(pEnd - pStart, 0);
  for (PetscInt f : faces) {
    PetscInt n;
    const PetscInt *cone;
    PetscCall(DMPlexGetConeSize(dm, f, &n));
    PetscCall(DMPlexGetCone(dm, f, &cone));
    for (PetscInt k = 0; k < n; ++k) ++count[cone[k] - pStart];
  }
  std::vector<PetscInt> total(count);
  PetscCall(DMGetPointSF(dm, &sf));
  PetscCall(PetscSFReduceBegin(sf, MPIU_INT, count.data(), total.data(), MPI_SUM));
  PetscCall(PetscSFReduceEnd(sf, MPIU_INT, count.data(), total.data(), MPI_SUM));
  PetscInt local = 0;
  for (PetscInt p = pStart; p < pEnd; ++p)
    if (!copy[p - pStart] && total[p - pStart] != 0 && total[p - pStart] != 2) ++local;
  PetscCallMPI(MPI_Allreduce(&local, open, 1, MPIU_INT, MPI_SUM, PetscObjectComm((PetscObject)dm)));
  PetscFunctionReturn(0);
}

}  // namespace

Eigen::Vector3d FollowerPressure::position(PetscInt v, const PetscScalar *x) const {
  return Eigen::Map<const Eigen::Vector3d>(x + verts_[v].loc);
}

PetscErrorCode FollowerPressure::setup(const Mesh &mesh, const std::vector<SurfaceLoad> &loads) {
  MPI_Comm comm;
  PetscInt pStart, pEnd;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)mesh.dm, &comm));
  PetscCall(DMPlexGetChart(mesh.dm, &pStart, &pEnd));
  std::vector<char> copy;  // copies of another rank's points: a face is counted by its owner only
  PetscCall(core::sharedLeafPoints(mesh.dm, &copy));
  for (const SurfaceLoad &load : loads) {
    if (load.kind != SurfaceLoad::Kind::Pressure) continue;
    const int set = static_cast<int>(loads_++);
    std::vector<PetscInt> owned;
    PetscInt open = 0;
    PetscCall(ownedGroupFacets(mesh, copy, load.set, "-load_pressure_" + load.set,
                               "a pressure acts on a closed boundary surface of a tet mesh", &owned));
    PetscCall(openEdges(mesh.dm, owned, pStart, pEnd, copy, &open));
    if (open > 0)
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
              "option -load_pressure_%s: the group is not a closed surface (%d edges not shared by exactly two of its "
              "faces); a follower pressure has a potential only on a closed surface (a cavity or a whole boundary)",
              load.set.c_str(), (int)open);
    double centroid[4] = {0, 0, 0, 0}, sums[4];
    for (PetscInt f : owned) {
      PetscInt ns;
      const PetscInt *supp;
      std::vector<PetscInt> vs, cell;
      PetscCall(closureVertices(mesh, f, &vs));
      PetscCall(DMPlexGetSupportSize(mesh.dm, f, &ns));
      PetscCall(DMPlexGetSupport(mesh.dm, f, &supp));
      if (ns != 1 || vs.size() != 3)
        SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
                "option -load_pressure_%s: the group has a face inside the body (a pressure acts on boundary faces)",
                load.set.c_str());
      std::array<PetscInt, 3> tri = {vs[0], vs[1], vs[2]};
      // Outward: away from the cell's fourth vertex.
      PetscCall(closureVertices(mesh, supp[0], &cell));
      Eigen::Vector3d inner = Eigen::Vector3d::Zero();
      for (PetscInt v : cell)
        if (std::find(tri.begin(), tri.end(), v) == tri.end()) inner = verts_[v].rest;
      const Eigen::Vector3d &X0 = verts_[tri[0]].rest;
      const Eigen::Vector3d n = (verts_[tri[1]].rest - X0).cross(verts_[tri[2]].rest - X0);
      if (n.dot(inner - X0) > 0.0) std::swap(tri[1], tri[2]);
      triangles_.push_back({tri, set});
      const double area = 0.5 * n.norm();
      for (PetscInt v : tri)
        for (int i = 0; i < 3; ++i) centroid[i] += area / 3.0 * verts_[v].rest[i];
      centroid[3] += area;
    }
    PetscCallMPI(MPI_Allreduce(centroid, sums, 4, MPI_DOUBLE, MPI_SUM, comm));
    center_.emplace_back(sums[0] / sums[3], sums[1] / sums[3], sums[2] / sums[3]);
    pressure_.push_back(load.value[0]);
    restVolume_.push_back(0.0);
  }
  for (const Triangle &t : triangles_)
    restVolume_[t.set] += kernels::triangleVolume(verts_[t.vertex[0]].rest, verts_[t.vertex[1]].rest,
                                                  verts_[t.vertex[2]].rest, center_[t.set], kernels::Order::Value)
                              .value;
  PetscFunctionReturn(0);
}

void FollowerPressure::addEnergy(const PetscScalar *x, double *energy, double *magnitude) const {
  double e = 0.0, mag = 0.0;
  for (const Triangle &t : triangles_) {
    const double v = kernels::triangleVolume(position(t.vertex[0], x), position(t.vertex[1], x),
                                             position(t.vertex[2], x), center_[t.set], kernels::Order::Value)
                         .value;
    e += s_ * pressure_[t.set] * v;
    mag += std::abs(s_ * pressure_[t.set] * v);
  }
  for (size_t k = 0; k < restVolume_.size(); ++k) {  // the datum V(X): zero at rest
    e -= s_ * pressure_[k] * restVolume_[k];
    mag += std::abs(s_ * pressure_[k] * restVolume_[k]);
  }
  *energy += e;
  *magnitude += mag;
}

void FollowerPressure::addGradient(const PetscScalar *x, PetscScalar *g) const {
  for (const Triangle &t : triangles_) {
    const auto d = kernels::triangleVolume(position(t.vertex[0], x), position(t.vertex[1], x), position(t.vertex[2], x),
                                           center_[t.set], kernels::Order::Gradient);
    for (int i = 0; i < 3; ++i) {
      const auto &vi = verts_[t.vertex[i]];
      for (int k = 0; k < 3; ++k)
        if (!vi.fixed(k)) g[vi.loc + k] += s_ * pressure_[t.set] * d.grad[3 * i + k];
    }
  }
}

PetscErrorCode FollowerPressure::addHessian(const PetscScalar *x, const HessianAssembly &how, Mat J) const {
  PetscFunctionBeginUser;
  for (const Triangle &t : triangles_) {
    if (productSkips<3, 3>(verts_, t.vertex, how)) continue;
    const auto d = kernels::triangleVolume(position(t.vertex[0], x), position(t.vertex[1], x), position(t.vertex[2], x),
                                           center_[t.set], kernels::Order::Hessian);
    const kernels::Mat<9, 9> H = kernels::filterEigenvalues<9>((s_ * pressure_[t.set]) * d.hess, how.filter.filter);
    const Eigen::Matrix<double, 9, 9, Eigen::RowMajor> K = H;
    PetscCall((addElementMatrix<3, 3>(verts_, t.vertex, K.data(), how, J)));
  }
  PetscFunctionReturn(0);
}

void FollowerPressure::addCurvature(const PetscScalar *x, const PetscScalar *const d[], int K, GramMatrix *q) const {
  for (const Triangle &t : triangles_) {
    Eigen::Matrix<double, 9, Eigen::Dynamic, 0, 9, kMaxGramDirections> A(9, K);
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < K; ++k)
        A.col(k).template segment<3>(3 * i) = Eigen::Map<const Eigen::Vector3d>(d[k] + verts_[t.vertex[i]].loc);
    const auto h = kernels::triangleVolume(position(t.vertex[0], x), position(t.vertex[1], x),
                                           position(t.vertex[2], x), center_[t.set], kernels::Order::Hessian);
    addGram(A, ((s_ * pressure_[t.set]) * h.hess).eval(), K, q);
  }
}

PetscInt FollowerPressure::offRankHessianValues() const {
  PetscInt blocks = 0;
  for (const Triangle &t : triangles_)
    for (PetscInt v : t.vertex) blocks += verts_[v].offRankFree() ? 3 : 0;
  return blocks * 9;
}

}  // namespace aries::fem
