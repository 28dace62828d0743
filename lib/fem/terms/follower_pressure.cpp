#include "fem/terms/follower_pressure.hpp"

#include "core/parallel.hpp"
#include "fem/terms/boundary_facets.hpp"
#include "kernels/psd_projection.hpp"

#include <petscdmplex.h>
#include <petscsf.h>

#include <algorithm>
#include <cmath>

namespace aries::fem {

namespace {

// Edges of the set's facets shared by an odd number of them, over all ranks (0: a closed surface; a boundary edge
// where two parts of the body touch, as voxels along an edge, has 4).
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
    if (!copy[p - pStart] && total[p - pStart] % 2 != 0) ++local;
  PetscCallMPI(MPI_Allreduce(&local, open, 1, MPIU_INT, MPI_SUM, PetscObjectComm((PetscObject)dm)));
  PetscFunctionReturn(0);
}

}  // namespace

template <class Face>
auto FollowerPressure<Face>::positions(const PressureFace &f, const PetscScalar *x) const -> kernels::Mat<kNodes, 3> {
  kernels::Mat<kNodes, 3> X;
  for (int a = 0; a < kNodes; ++a) X.row(a) = Eigen::Map<const Eigen::Vector3d>(x + verts_[f.vertex[a]].loc).transpose();
  return X;
}

template <class Face>
auto FollowerPressure<Face>::restPositions(const PressureFace &f) const -> kernels::Mat<kNodes, 3> {
  kernels::Mat<kNodes, 3> X;
  for (int a = 0; a < kNodes; ++a) X.row(a) = verts_[f.vertex[a]].rest.transpose();
  return X;
}

template <class Face>
PetscErrorCode FollowerPressure<Face>::setup(const Mesh &mesh, const std::vector<SurfaceLoad> &loads) {
  MPI_Comm comm;
  PetscInt pStart, pEnd;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)mesh.dm, &comm));
  PetscCall(DMPlexGetChart(mesh.dm, &pStart, &pEnd));
  std::vector<char> copy;  // copies of another rank's points: a face is counted by its owner only
  PetscCall(core::sharedLeafPoints(mesh.dm, &copy));
  for (const SurfaceLoad &load : loads) {
    if (load.kind != SurfaceLoad::Kind::Pressure || load.dead) continue;
    const int set = static_cast<int>(loads_++);
    const std::string option = "-load_pressure_" + load.set;
    const std::string purpose = "a follower pressure acts on a closed boundary surface of a volume mesh; "
                                "-load_pressure_" + load.set + "_kind dead loads an open one";
    std::vector<PetscInt> owned;
    PetscInt open = 0;
    PetscCall(ownedGroupFacets(mesh, copy, load.set, option, purpose.c_str(), &owned));
    PetscCall(openEdges(mesh.dm, owned, pStart, pEnd, copy, &open));
    if (open > 0)
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
              "option -load_pressure_%s: the group is not a closed surface (%d edges shared by an odd number of its "
              "faces); a follower pressure has a potential only on a closed surface (a cavity or a whole boundary): "
              "-load_pressure_%s_kind dead gives the dead pressure, which any surface can carry",
              load.set.c_str(), (int)open, load.set.c_str());
    std::vector<OrientedFacet> facets;
    PetscCall(orientBoundaryFacets(mesh, verts_, owned, option, &facets));
    const size_t first = faces_.size();
    if constexpr (kNodes == 6) {
      std::vector<std::array<PetscInt, 6>> quadratic;
      PetscCall(quadraticGroupFaces(mesh, verts_, owned, option, &quadratic));
      for (const auto &q : quadratic) faces_.push_back(PressureFace{q, set});
    } else {
      for (const OrientedFacet &f : facets) {
        if (f.count != kNodes)
          SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s: the group has a facet with %d vertices",
                  option.c_str(), f.count);
        PressureFace face;
        face.set = set;
        std::copy(f.vertex.begin(), f.vertex.begin() + kNodes, face.vertex.begin());
        faces_.push_back(face);
      }
    }
    // The set's rest centroid (area-weighted over its facets: the reference point only sets the pieces' round-off).
    double centroid[4] = {0, 0, 0, 0}, sums[4];
    for (const OrientedFacet &f : facets) {
      const double area = restAreaVector(verts_, f).norm();
      for (int k = 0; k < f.count; ++k)
        for (int i = 0; i < 3; ++i) centroid[i] += area / f.count * verts_[f.vertex[k]].rest[i];
      centroid[3] += area;
    }
    PetscCallMPI(MPI_Allreduce(centroid, sums, 4, MPI_DOUBLE, MPI_SUM, comm));
    center_.emplace_back(sums[0] / sums[3], sums[1] / sums[3], sums[2] / sums[3]);
    pressure_.push_back(load.value[0]);
    double v = 0.0;
    for (size_t k = first; k < faces_.size(); ++k)
      v += kernels::faceVolume<Face>(restPositions(faces_[k]), center_.back(), kernels::Order::Value).value;
    restVolume_.push_back(v);
  }
  PetscFunctionReturn(0);
}

template <class Face>
void FollowerPressure<Face>::addEnergy(const PetscScalar *x, double *energy, double *magnitude) const {
  double e = 0.0, mag = 0.0;
  for (const PressureFace &f : faces_) {
    const double v = kernels::faceVolume<Face>(positions(f, x), center_[f.set], kernels::Order::Value).value;
    e += s_ * pressure_[f.set] * v;
    mag += std::abs(s_ * pressure_[f.set] * v);
  }
  for (size_t k = 0; k < restVolume_.size(); ++k) {  // the datum V(X): zero at rest
    e -= s_ * pressure_[k] * restVolume_[k];
    mag += std::abs(s_ * pressure_[k] * restVolume_[k]);
  }
  *energy += e;
  *magnitude += mag;
}

template <class Face>
void FollowerPressure<Face>::addGradient(const PetscScalar *x, PetscScalar *g) const {
  for (const PressureFace &f : faces_) {
    const auto d = kernels::faceVolume<Face>(positions(f, x), center_[f.set], kernels::Order::Gradient);
    for (int a = 0; a < kNodes; ++a) {
      const auto &va = verts_[f.vertex[a]];
      for (int k = 0; k < 3; ++k)
        if (!va.fixed(k)) g[va.loc + k] += s_ * pressure_[f.set] * d.grad[3 * a + k];
    }
  }
}

template <class Face>
PetscErrorCode FollowerPressure<Face>::addHessian(const PetscScalar *x, const HessianAssembly &how, Mat J) const {
  constexpr int N = 3 * kNodes;
  PetscFunctionBeginUser;
  for (const PressureFace &f : faces_) {
    if (productSkips<kNodes, 3>(verts_, f.vertex, how)) continue;
    const auto d = kernels::faceVolume<Face>(positions(f, x), center_[f.set], kernels::Order::Hessian);
    const kernels::Mat<N, N> H = kernels::filterEigenvalues<N>((s_ * pressure_[f.set]) * d.hess, how.filter.filter);
    const Eigen::Matrix<double, N, N, Eigen::RowMajor> K = H;
    PetscCall((addElementMatrix<kNodes, 3>(verts_, f.vertex, K.data(), how, J)));
  }
  PetscFunctionReturn(0);
}

template <class Face>
void FollowerPressure<Face>::addCurvature(const PetscScalar *x, const PetscScalar *const d[], int K,
                                          GramMatrix *q) const {
  constexpr int N = 3 * kNodes;
  for (const PressureFace &f : faces_) {
    Eigen::Matrix<double, N, Eigen::Dynamic, 0, N, kMaxGramDirections> A(N, K);
    for (int a = 0; a < kNodes; ++a)
      for (int k = 0; k < K; ++k)
        A.col(k).template segment<3>(3 * a) = Eigen::Map<const Eigen::Vector3d>(d[k] + verts_[f.vertex[a]].loc);
    const auto h = kernels::faceVolume<Face>(positions(f, x), center_[f.set], kernels::Order::Hessian);
    addGram(A, ((s_ * pressure_[f.set]) * h.hess).eval(), K, q);
  }
}

template <class Face>
PetscInt FollowerPressure<Face>::offRankHessianValues() const {
  PetscInt blocks = 0;
  for (const PressureFace &f : faces_)
    for (PetscInt v : f.vertex) blocks += verts_[v].offRankFree() ? 3 * kNodes : 0;
  return blocks * 3;
}

template class FollowerPressure<kernels::face::Tri3>;
template class FollowerPressure<kernels::face::Quad4>;
template class FollowerPressure<kernels::face::Tri6>;

}  // namespace aries::fem
