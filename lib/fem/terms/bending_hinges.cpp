#include "fem/terms/bending_hinges.hpp"

#include <petscdmplex.h>
#include <petscsf.h>

namespace aries::fem {

PetscErrorCode BendingHinges::build(DM dm, PetscInt vStart,
                                    const std::function<PetscInt(PetscInt, PetscInt, PetscInt)> &opposite) {
  PetscInt eStart, eEnd, nleaves;
  const PetscInt *ilocal;
  PetscSF sf;
  PetscFunctionBeginUser;
  PetscCall(DMPlexGetDepthStratum(dm, 1, &eStart, &eEnd));
  PetscCall(DMGetPointSF(dm, &sf));
  PetscCall(PetscSFGetGraph(sf, nullptr, &nleaves, &ilocal, nullptr));
  std::vector<char> leaf(eEnd - eStart, 0);  // edges owned by another rank
  for (PetscInt i = 0; i < nleaves; ++i) {
    const PetscInt q = ilocal ? ilocal[i] : i;
    if (q >= eStart && q < eEnd) leaf[q - eStart] = 1;
  }
  for (PetscInt e = eStart; e < eEnd; ++e) {
    if (leaf[e - eStart]) continue;
    PetscInt nsupp;
    const PetscInt *supp, *cone;
    PetscCall(DMPlexGetSupportSize(dm, e, &nsupp));
    if (nsupp != 2) continue;  // boundary edge
    PetscCall(DMPlexGetSupport(dm, e, &supp));
    PetscCall(DMPlexGetCone(dm, e, &cone));
    Hinge h;
    h.vertex[0] = cone[0] - vStart;
    h.vertex[1] = cone[1] - vStart;
    for (int k = 0; k < 2; ++k) h.vertex[2 + k] = opposite(supp[k], h.vertex[0], h.vertex[1]);
    h.rest = kernels::bendingHinge(verts_[h.vertex[0]].rest, verts_[h.vertex[1]].rest, verts_[h.vertex[2]].rest,
                                   verts_[h.vertex[3]].rest);
    hinges_.push_back(h);
  }
  PetscFunctionReturn(0);
}

void BendingHinges::addEnergy(const PetscScalar *x, double *energy, double *magnitude) const {
  double e = 0.0;
  Eigen::Vector3d xs[4];
  for (const Hinge &h : hinges_) {
    positions(h, x, xs);
    e += kernels::quadraticBending(h.rest, xs, stiffness_, kernels::Order::Value).value;
  }
  *energy += e;
  *magnitude += e;  // every hinge's energy is >= 0
}

void BendingHinges::addGradient(const PetscScalar *x, PetscScalar *g) const {
  Eigen::Vector3d xs[4];
  for (const Hinge &h : hinges_) {
    positions(h, x, xs);
    const auto d = kernels::quadraticBending(h.rest, xs, stiffness_, kernels::Order::Gradient);
    for (int i = 0; i < 4; ++i)
      for (int k = 0; k < 3; ++k) g[verts_[h.vertex[i]].loc + k] += d.grad[3 * i + k];
  }
}

PetscErrorCode BendingHinges::addHessian(const PetscScalar *x, const HessianAssembly &how, Mat J) const {
  Eigen::Vector3d xs[4];
  PetscFunctionBeginUser;
  for (const Hinge &h : hinges_) {
    if (productSkips<4, 3>(verts_, h.vertex, how)) continue;
    positions(h, x, xs);
    const auto d = kernels::quadraticBending(h.rest, xs, stiffness_, kernels::Order::Hessian);
    const Eigen::Matrix<double, 12, 12, Eigen::RowMajor> K = d.hess;
    PetscCall((addElementMatrix<4, 3>(verts_, h.vertex, K.data(), how, J)));  // as the cells' (the same stash)
  }
  PetscFunctionReturn(0);
}

void BendingHinges::addCurvature(const PetscScalar *x, const PetscScalar *const d[], int K, GramMatrix *q) const {
  Eigen::Vector3d xs[4];
  for (const Hinge &h : hinges_) {
    Eigen::Matrix<double, 12, Eigen::Dynamic, 0, 12, kMaxGramDirections> A(12, K);
    positions(h, x, xs);
    for (int i = 0; i < 4; ++i)
      for (int k = 0; k < K; ++k)
        A.col(k).template segment<3>(3 * i) = Eigen::Map<const Eigen::Vector3d>(d[k] + verts_[h.vertex[i]].loc);
    addGram(A, kernels::quadraticBending(h.rest, xs, stiffness_, kernels::Order::Hessian).hess, K, q);
  }
}

PetscInt BendingHinges::offRankHessianValues() const {
  PetscInt blocks = 0;
  for (const Hinge &h : hinges_)
    for (PetscInt v : h.vertex) blocks += verts_[v].offRankFree() ? 4 : 0;
  return blocks * 9;
}

}  // namespace aries::fem
