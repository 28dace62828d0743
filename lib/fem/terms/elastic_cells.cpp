#include "fem/terms/elastic_cells.hpp"

#include <cmath>

namespace aries::fem {

template <int R, int C>
void ElasticCells<R, C>::addEnergy(const PetscScalar *x, double *energy, double *magnitude) const {
  double e = 0.0, mag = 0.0;
  for (size_t c = 0; c < cells_.size(); ++c) {
    if (!cells_[c].owned) continue;
    const double ec = cells_[c].measure * energyDensity(c, x);
    e += ec;
    mag += std::abs(ec);
  }
  *energy += e;
  *magnitude += mag;
}

template <int R, int C>
void ElasticCells<R, C>::addGradient(const PetscScalar *x, PetscScalar *g) const {
  for (size_t c = 0; c < cells_.size(); ++c) {
    const Cell &cell = cells_[c];
    if (!cell.owned) continue;
    const auto d = energies::evaluateEnergy<R, C>(materialOf(c), dataOf(c), deformationGradient(c, x),
                                                  kernels::Order::Gradient);
    const kernels::Mat<R, C> P = cell.measure * kernels::unflatten<R, C>(d.grad);
    for (int v = 0; v < NV; ++v) {
      const kernels::Vec<R> gv = P * cell.W.row(v).transpose();
      PetscScalar *gp = g + verts_[cell.vertex[v]].loc;
      for (int i = 0; i < R; ++i) gp[i] += gv[i];
    }
  }
}

template <int R, int C>
PetscErrorCode ElasticCells<R, C>::addHessian(const PetscScalar *x, const HessianAssembly &how, Mat J) const {
  PetscFunctionBeginUser;
  Eigen::Matrix<double, NDOF, NDOF, Eigen::RowMajor> K;
  for (size_t c = 0; c < cells_.size(); ++c) {
    const Cell &cell = cells_[c];
    if (!cell.owned) continue;
    const auto d =
        energies::evaluateFilteredEnergy<R, C>(materialOf(c), dataOf(c), deformationGradient(c, x), how.filter);
    const kernels::Mat<NF, NF> H = cell.measure * d.hess;
    // K[(v,i),(u,k)] = sum_jl H[(i,j),(k,l)] W(v,j) W(u,l)
    Eigen::Matrix<double, NF, NDOF> HB;  // H * B, B[(k,l),(u,k')] = delta_kk' W(u,l)
    for (int row = 0; row < NF; ++row)
      for (int u = 0; u < NV; ++u)
        for (int k = 0; k < R; ++k) {
          double s = 0.0;
          for (int l = 0; l < C; ++l) s += H(row, k * C + l) * cell.W(u, l);
          HB(row, u * R + k) = s;
        }
    for (int v = 0; v < NV; ++v)
      for (int i = 0; i < R; ++i)
        for (int col = 0; col < NDOF; ++col) {
          double s = 0.0;
          for (int j = 0; j < C; ++j) s += cell.W(v, j) * HB(i * C + j, col);
          K(v * R + i, col) = s;
        }
    PetscCall((addElementMatrix<NV, R>(verts_, cell.vertex, K.data(), how, J)));
  }
  PetscFunctionReturn(0);
}

template <int R, int C>
void ElasticCells<R, C>::addCurvature(const PetscScalar *x, const PetscScalar *const d[], int K, GramMatrix *q) const {
  for (size_t c = 0; c < cells_.size(); ++c) {
    if (!cells_[c].owned) continue;
    const auto e = energies::evaluateEnergy<R, C>(materialOf(c), dataOf(c), deformationGradient(c, x),
                                                  kernels::Order::Hessian);
    Eigen::Matrix<double, NF, Eigen::Dynamic, 0, NF, kMaxGramDirections> A(NF, K);
    for (int k = 0; k < K; ++k) A.col(k) = kernels::flatten<R, C>(deformationGradient(c, d[k]));
    addGram(A, (cells_[c].measure * e.hess).eval(), K, q);
  }
}

template <int R, int C>
PetscInt ElasticCells<R, C>::offRankHessianValues() const {
  PetscInt blocks = 0;
  for (const Cell &cell : cells_)
    if (cell.owned)
      for (int v = 0; v < NV; ++v) blocks += verts_[cell.vertex[v]].offRankFree() ? NV : 0;
  return blocks * R * R;
}

template <int R, int C>
PetscInt ElasticCells<R, C>::updateBarrierFallback(const std::vector<double> &alpha, double threshold) {
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

template class ElasticCells<3, 3>;
template class ElasticCells<2, 2>;
template class ElasticCells<3, 2>;

}  // namespace aries::fem
