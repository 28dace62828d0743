#include "fem/terms/elastic_cells.hpp"

#include "kernels/psd_projection.hpp"

#include <cmath>

namespace aries::fem {

template <int R, int C, int NV>
void ElasticCells<R, C, NV>::addEnergy(const PetscScalar *x, double *energy, double *magnitude) const {
  double e = 0.0, mag = 0.0;
  forEachOwnedCell([&](size_t c) {
    for (int q = 0; q < NQ; ++q) {
      const double eq = cells_[c].weight[q] *
                        energies::evaluateEnergy<R, C>(materialOf(c), dataOf(c), deformationGradient(c, q, x),
                                                       kernels::Order::Value).value;
      e += eq;
      mag += std::abs(eq);
    }
  });
  *energy += e;
  *magnitude += mag;
}

template <int R, int C, int NV>
void ElasticCells<R, C, NV>::addGradient(const PetscScalar *x, PetscScalar *g) const {
  forEachOwnedCell([&](size_t c) {
    const Cell &cell = cells_[c];
    kernels::Vec<NDOF> ge = kernels::Vec<NDOF>::Zero();
    for (int q = 0; q < NQ; ++q) {
      const auto d = energies::evaluateEnergy<R, C>(materialOf(c), dataOf(c), deformationGradient(c, q, x),
                                                    kernels::Order::Gradient);
      kernels::addPointGradient<R, C, NV>(cell.weight[q] * kernels::unflatten<R, C>(d.grad), cell.W[q], &ge);
    }
    for (int v = 0; v < NV; ++v) {
      PetscScalar *gp = g + verts_[cell.vertex[v]].loc;
      for (int i = 0; i < R; ++i) gp[i] += ge[v * R + i];
    }
  });
}

template <int R, int C, int NV>
PetscErrorCode ElasticCells<R, C, NV>::addHessian(const PetscScalar *x, const HessianAssembly &how, Mat J) const {
  PetscFunctionBeginUser;
  Eigen::Matrix<double, NDOF, NDOF, Eigen::RowMajor> K;
  bool direct = false;  // straight into the matrix's value arrays (element_scatter.hpp)
  if (J && !how.product())
    PetscCall(scatter_.prepare(
        J, verts_, cells_.size(), [&](size_t c) { return cells_[c].vertex.data(); },
        [&](size_t c) { return cells_[c].owned; }, &direct));
  if (direct) PetscCall(scatter_.begin());
  PetscErrorCode ierr = 0;  // the first failed insertion: the other cells are skipped and it is returned below
  forEachOwnedCell([&](size_t c) {
    const Cell &cell = cells_[c];
    if (ierr || productSkips<NV, R>(verts_, cell.vertex, how)) return;
    K.setZero();
    const int points = how.patternOnly ? 0 : NQ;  // pattern mode: the insertion of a zero matrix is all that counts
    for (int q = 0; q < points; ++q) {  // filtered per point, or summed unfiltered and the element filtered below
      const auto d = how.wholeElement ? energies::evaluateEnergy<R, C>(materialOf(c), dataOf(c),
                                                                       deformationGradient(c, q, x),
                                                                       kernels::Order::Hessian)
                                      : energies::evaluateFilteredEnergy<R, C>(materialOf(c), dataOf(c),
                                                                               deformationGradient(c, q, x), how.filter);
      kernels::addPointHessian<R, C, NV>((cell.weight[q] * d.hess).eval(), cell.W[q], &K);
    }
    if (how.wholeElement && how.filter.filter != kernels::EigenFilter::None && !how.patternOnly) {
      K = kernels::filterEigenvalues<NDOF>(kernels::Mat<NDOF, NDOF>(K), how.filter.filter);
    }
    ierr = direct ? scatter_.add(J, verts_, c, cell.vertex, K.data())
                  : addElementMatrix<NV, R>(verts_, cell.vertex, K.data(), how, J);
  });
  PetscCall(ierr);
  if (direct) PetscCall(scatter_.end());
  PetscFunctionReturn(0);
}

template <int R, int C, int NV>
void ElasticCells<R, C, NV>::addCurvature(const PetscScalar *x, const PetscScalar *const d[], int K,
                                          GramMatrix *q) const {
  forEachOwnedCell([&](size_t c) {
    for (int p = 0; p < NQ; ++p) {
      const auto e = energies::evaluateEnergy<R, C>(materialOf(c), dataOf(c), deformationGradient(c, p, x),
                                                    kernels::Order::Hessian);
      Eigen::Matrix<double, NF, Eigen::Dynamic, 0, NF, kMaxGramDirections> A(NF, K);
      for (int k = 0; k < K; ++k) A.col(k) = kernels::flatten<R, C>(deformationGradient(c, p, d[k]));
      addGram(A, (cells_[c].weight[p] * e.hess).eval(), K, q);
    }
  });
}

template <int R, int C, int NV>
PetscInt ElasticCells<R, C, NV>::offRankHessianValues() const {
  PetscInt blocks = 0;
  for (const Cell &cell : cells_)
    if (cell.owned)
      for (int v = 0; v < NV; ++v) blocks += verts_[cell.vertex[v]].offRankFree() ? NV : 0;
  return blocks * R * R;
}

template <int R, int C, int NV>
PetscInt ElasticCells<R, C, NV>::updateBarrierFallback(const std::vector<double> &alpha, double threshold) {
  if (mollified_.empty()) {
    mollified_ = materials_;
    for (auto &m : mollified_)
      if (m.singularity.mode == energies::SingularityMode::Barrier) m.singularity.mode = energies::SingularityMode::Mollifier;
  }
  PetscInt count = 0;
  fallback_.assign(cells_.size(), 0);
  for (size_t c = 0; c < cells_.size(); ++c)
    if (!(alpha[c] > threshold)) {
      fallback_[c] = 1;
      ++count;
    }
  return count;
}

ARIES_INSTANTIATE_FOR_ELEMENT_TYPES(ElasticCells)

}  // namespace aries::fem
