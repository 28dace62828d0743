// What a state looks like beyond its energy: per-cell alpha, guard, energy density, stress measures and regions; the
// barrier mode's fallback; reactions on the Dirichlet sets; the largest displacement; the owned vertices' and cells'
// values with their natural (gmsh-order) ids for output; and the rotational form of a Newton step (the spin of a
// displacement field per vertex, -newton_rotation).
#include "fem/discretization_impl.hpp"

#include "kernels/dense_decompositions.hpp"

#include <cmath>
#include <limits>

namespace aries::fem {

template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::updateBarrierFallback(Vec xLocal, double threshold, PetscInt *count) {
  PetscFunctionBeginUser;
  bool anyBarrier = false;
  for (const auto &m : materials_) anyBarrier = anyBarrier || m.singularity.mode == energies::SingularityMode::Barrier;
  PetscInt local = 0;
  if (anyBarrier) {
    std::vector<double> alpha;
    PetscCall(cellAlpha(xLocal, &alpha));
    local = cells_.updateBarrierFallback(alpha, threshold);
  }
  PetscCallMPI(MPI_Allreduce(&local, count, 1, MPIU_INT, MPI_SUM, comm()));
  PetscFunctionReturn(0);
}

namespace {

// The owned cells evaluated in singularity mode `mode` whose energies have I4/I6 terms and some point's alpha inside
// the material's band, `inBand(material, F, alpha)`, at a local state (collective count).
template <int R, int C, class Cells, class InBand>
PetscErrorCode countCellsInSingularBand(MPI_Comm comm, const Cells &cells, int points, Vec xLocal,
                                        energies::SingularityMode mode, InBand inBand, PetscInt *count) {
  const PetscScalar *x;
  PetscFunctionBeginUser;
  PetscInt local = 0;
  PetscCall(VecGetArrayRead(xLocal, &x));
  for (size_t c = 0; c < cells.size(); ++c) {
    const energies::Material &m = cells.materialOf(c);
    if (!cells.cells()[c].owned || m.singularity.mode != mode || !energies::energyContainsStretchInvariant(m.kind))
      continue;
    for (int p = 0; p < points; ++p) {  // a cell counts once, if any of its points is in the band
      const kernels::Mat<R, C> F = cells.deformationGradient(c, p, x);
      if (inBand(m, F, energies::elementAlpha<R, C>(F))) {
        ++local;
        break;
      }
    }
  }
  PetscCall(VecRestoreArrayRead(xLocal, &x));
  PetscCallMPI(MPI_Allreduce(&local, count, 1, MPIU_INT, MPI_SUM, comm));
  PetscFunctionReturn(0);
}

}  // namespace

template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::barrierActiveCells(Vec xLocal, PetscInt *count) const {
  return countCellsInSingularBand<R, C>(
      comm(), cells_, NQ, xLocal, energies::SingularityMode::Barrier,
      [](const energies::Material &m, const kernels::Mat<R, C> &, double a) {
        return a > 0.0 && a < m.singularity.barrier.eps;
      },
      count);
}

template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::mollifierBandCells(Vec xLocal, PetscInt *count) const {
  return countCellsInSingularBand<R, C>(
      comm(), cells_, NQ, xLocal, energies::SingularityMode::Mollifier,
      [](const energies::Material &m, const kernels::Mat<R, C> &F, double alpha) {
        const kernels::MollifierParams &band = m.singularity.mollifier;
        return kernels::inMollifierBand(kernels::mollifierCoordinate<R, C>(F, alpha, band), band, kMollifierBandEdge);
      },
      count);
}

template <int R, int C, int NV>
void DiscretizationT<R, C, NV>::mollifierBandTop(std::vector<double> *top) const {
  top->resize(cells_.size());
  for (size_t c = 0; c < cells_.size(); ++c) {
    const energies::Material &m = cells_.materialOf(c);
    const bool mollified = m.singularity.mode == energies::SingularityMode::Mollifier &&
                           energies::energyContainsStretchInvariant(m.kind);
    (*top)[c] = mollified ? m.singularity.mollifier.eps : 0.0;
  }
}

template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::cellAlpha(Vec xLocal, std::vector<double> *alpha) const {
  const PetscScalar *x;
  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(xLocal, &x));
  elasticGuards(x, std::numeric_limits<double>::infinity(), alpha);  // exact everywhere: alpha
  PetscCall(VecRestoreArrayRead(xLocal, &x));
  PetscFunctionReturn(0);
}

// Each cell's guard value (ElasticCells::guard), the focus's cells only while a local solve focuses (the others +inf).
template <int R, int C, int NV>
void DiscretizationT<R, C, NV>::elasticGuards(const PetscScalar *x, double exactBelow, std::vector<double> *guard) const {
  if (cells_.focused()) {
    guard->assign(cells_.size(), std::numeric_limits<double>::infinity());
    for (size_t c : cells_.focus()) (*guard)[c] = cells_.guard(c, x, exactBelow);
  } else {
    guard->resize(cells_.size());
    for (size_t c = 0; c < cells_.size(); ++c) (*guard)[c] = cells_.guard(c, x, exactBelow);
  }
}

template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::setFocus(Vec markLocal) {
  PetscFunctionBeginUser;
  if (!markLocal) {
    cells_.setFocus(nullptr);
    PetscFunctionReturn(0);
  }
  const PetscScalar *m;
  std::vector<char> mask(verts_.size(), 0);
  PetscCall(VecGetArrayRead(markLocal, &m));
  for (size_t v = 0; v < verts_.size(); ++v)
    for (PetscInt i = 0; i < dofs_; ++i)
      if (m[verts_[v].loc + i] != 0.0) mask[v] = 1;
  PetscCall(VecRestoreArrayRead(markLocal, &m));
  cells_.setFocus(&mask);
  PetscFunctionReturn(0);
}

template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::markFocusVertices(Vec outLocal) const {
  PetscScalar *m;
  PetscFunctionBeginUser;
  PetscCall(VecGetArray(outLocal, &m));
  for (size_t c : cells_.focus())
    for (PetscInt v : cells_.cells()[c].vertex)
      for (PetscInt i = 0; i < dofs_; ++i) m[verts_[v].loc + i] = 1.0;
  PetscCall(VecRestoreArray(outLocal, &m));
  PetscFunctionReturn(0);
}

template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::cellGuard(Vec xLocal, double exactBelow, std::vector<double> *guard) const {
  const PetscScalar *x;
  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(xLocal, &x));
  elasticGuards(x, exactBelow, guard);
  if constexpr (R == 2 && C == 2) {
    if (keepOrientation_)
      for (size_t c = 0; c < cells_.size(); ++c)
        (*guard)[c] = std::min((*guard)[c], cells_.deformationGradient(c, 0, x).determinant());
  }
  PetscCall(VecRestoreArrayRead(xLocal, &x));
  PetscFunctionReturn(0);
}

// The cells' guard values exact below the smallest alpha found so far: a cell whose bound clears it cannot be the
// minimum, and the cell that is has its alpha below every earlier bound, so it is taken exactly.
template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::minAlpha(Vec xLocal, PetscReal *min) const {
  const PetscScalar *x;
  PetscFunctionBeginUser;
  double local = PETSC_MAX_REAL;
  PetscCall(VecGetArrayRead(xLocal, &x));
  for (size_t c = 0; c < cells_.size(); ++c) local = std::min(local, cells_.guard(c, x, local));
  PetscCall(VecRestoreArrayRead(xLocal, &x));
  PetscCallMPI(MPI_Allreduce(&local, min, 1, MPI_DOUBLE, MPI_MIN, comm()));
  PetscFunctionReturn(0);
}

template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::cellQuantities(Vec xLocal, CellQuantities *q) const {
  const PetscScalar *x;
  PetscFunctionBeginUser;
  q->alpha.resize(cells_.size());
  q->energyDensity.resize(cells_.size());
  PetscCall(VecGetArrayRead(xLocal, &x));
  for (size_t c = 0; c < cells_.size(); ++c) {
    q->alpha[c] = cells_.alpha(c, x);
    q->energyDensity[c] = cells_.energyDensity(c, x);
  }
  PetscCall(VecRestoreArrayRead(xLocal, &x));
  PetscFunctionReturn(0);
}

template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::cellStressMeasures(Vec xLocal, std::vector<kernels::StressMeasures> *out) const {
  const PetscScalar *x;
  PetscFunctionBeginUser;
  out->resize(cells_.size());
  PetscCall(VecGetArrayRead(xLocal, &x));
  for (size_t c = 0; c < cells_.size(); ++c) {
    const Cell &cell = cells_.cells()[c];
    // A hexahedron's measures: the average over its points, weighted by the points' measure.
    kernels::StressMeasures mean = NQ == 1 ? kernels::StressMeasures{} : kernels::StressMeasures::zero();
    for (int p = 0; p < NQ; ++p) {
      kernels::Mat<3, C> Frest = kernels::Mat<3, C>::Zero();  // the cell's chart -> rest shape
      for (int v = 0; v < NV; ++v) Frest += verts_[cell.vertex[v]].rest * cell.W[p].row(v);
      const kernels::Mat<R, C> F = cells_.deformationGradient(c, p, x);
      const auto d =
          energies::evaluateEnergy<R, C>(cells_.materialOf(c), cells_.dataOf(c), F, kernels::Order::Gradient);
      const kernels::StressMeasures sp = kernels::stressMeasures<R, C>(F, kernels::unflatten<R, C>(d.grad), Frest);
      if constexpr (NQ == 1) mean = sp;
      else mean.accumulate(sp, cell.weight[p] / cell.measure);
    }
    (*out)[c] = mean;
  }
  PetscCall(VecRestoreArrayRead(xLocal, &x));
  PetscFunctionReturn(0);
}

template <int R, int C, int NV>
void DiscretizationT<R, C, NV>::cellRegions(std::vector<double> *regions) const {
  regions->resize(cells_.size());
  for (size_t c = 0; c < cells_.size(); ++c) (*regions)[c] = cells_.cells()[c].region;
}

template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::ownedVertexReactions(Vec xLocal, std::vector<double> *values) const {
  PetscFunctionBeginUser;
  Vec g;
  PetscCall(VecDuplicate(xLocal, &g));
  PetscCall(gradient(xLocal, g));  // each rank: its own cells' share at every local vertex
  const PetscScalar *ga;
  PetscCall(VecGetArrayRead(g, &ga));
  std::vector<double> perVertex(3 * verts_.size(), 0.0);
  for (size_t v = 0; v < verts_.size(); ++v)  // the support force only: zero in the free components
    for (int i = 0; i < R; ++i)
      if (verts_[v].bcSet >= 0 && verts_[v].fixed(i)) perVertex[3 * v + i] = ga[verts_[v].loc + i];
  PetscCall(VecRestoreArrayRead(g, &ga));
  PetscCall(VecDestroy(&g));
  PetscCall(sumOverSharedVertices(*mesh_, 3, &perVertex));  // every rank's share
  ownedVertexRows(3, [&](size_t v, double *out) { std::copy_n(&perVertex[3 * v], 3, out); }, values);
  PetscFunctionReturn(0);
}

template <int R, int C, int NV>
void DiscretizationT<R, C, NV>::ownedVertexMarkers(std::vector<double> *values) const {
  ownedVertexRows(1, [&](size_t v, double *out) { out[0] = verts_[v].bcSet + 1.0; }, values);
}

template <int R, int C, int NV>
void DiscretizationT<R, C, NV>::ownedVertexRows(int comps, const std::function<void(size_t, double *)> &value,
                                            std::vector<double> *values) const {
  values->clear();
  std::vector<double> one(comps);
  for (size_t v = 0; v < verts_.size(); ++v) {
    if (!verts_[v].owned) continue;
    value(v, one.data());
    values->insert(values->end(), one.begin(), one.end());
  }
}

template <int R, int C, int NV>
void DiscretizationT<R, C, NV>::ownedVertexIds(std::vector<PetscInt> *natural, std::vector<PetscInt> *local) const {
  natural->clear();
  if (local) local->clear();
  for (size_t v = 0; v < verts_.size(); ++v)
    if (verts_[v].owned) {
      natural->push_back(mesh_->naturalVertex[v]);
      if (local) local->push_back(static_cast<PetscInt>(v));
    }
}

template <int R, int C, int NV>
void DiscretizationT<R, C, NV>::ownedCellIds(std::vector<PetscInt> *natural) const {
  natural->clear();
  for (size_t c = 0; c < cells_.size(); ++c)
    if (cells_.cells()[c].owned) natural->push_back(mesh_->naturalCell[c]);
}

template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::reactionForce(Vec xLocal, size_t set, Eigen::Vector3d *force) const {
  PetscFunctionBeginUser;
  Vec g;
  PetscCall(VecDuplicate(xLocal, &g));
  PetscCall(gradient(xLocal, g));  // Dirichlet vertices carry only elastic contributions of this rank's cells
  const PetscScalar *ga;
  PetscCall(VecGetArrayRead(g, &ga));
  double f[3] = {0, 0, 0}, tot[3];
  for (const auto &vi : verts_)  // each component to the set that prescribes it
    for (int i = 0; i < R; ++i)
      if (vi.fixedBy[i] == static_cast<int>(set)) f[i] += ga[vi.loc + i];
  PetscCall(VecRestoreArrayRead(g, &ga));
  PetscCall(VecDestroy(&g));
  PetscCallMPI(MPI_Allreduce(f, tot, 3, MPI_DOUBLE, MPI_SUM, comm()));
  *force = Eigen::Vector3d(tot[0], tot[1], tot[2]);
  PetscFunctionReturn(0);
}

template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::maxDisplacement(Vec xLocal, PetscReal *value) const {
  const PetscScalar *x;
  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(xLocal, &x));
  double m = 0.0;
  for (const auto &vi : verts_) {
    double d2 = 0.0;
    for (int i = 0; i < R; ++i) d2 += (x[vi.loc + i] - vi.rest[i]) * (x[vi.loc + i] - vi.rest[i]);
    m = std::max(m, std::sqrt(d2));
  }
  PetscCall(VecRestoreArrayRead(xLocal, &x));
  PetscCallMPI(MPI_Allreduce(&m, value, 1, MPI_DOUBLE, MPI_MAX, comm()));
  PetscFunctionReturn(0);
}

template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::vertexSpin(Vec xLocal, Vec dLocal, std::vector<double> *spin) const {
  PetscFunctionBeginUser;
  spin->assign(3 * verts_.size(), 0.0);
  if constexpr (R == 3 && C == 3) {
    const PetscScalar *x, *d;
    std::vector<double> sum(4 * verts_.size(), 0.0);  // volume-weighted w and the weight, per local vertex
    PetscCall(VecGetArrayRead(xLocal, &x));
    PetscCall(VecGetArrayRead(dLocal, &d));
    for (size_t c = 0; c < cells_.size(); ++c) {
      const auto &cell = cells_.cells()[c];
      if (!cell.owned) continue;
      for (int p = 0; p < NQ; ++p) {
        const kernels::Mat<3, 3> F = cells_.deformationGradient(c, p, x);
        if (!(F.determinant() > 0.25)) continue;  // inverted or collapsed: its spin says nothing
        const kernels::Mat<3, 3> G = cells_.deformationGradient(c, p, d) * F.inverse();
        const Eigen::Vector3d w(0.5 * (G(2, 1) - G(1, 2)), 0.5 * (G(0, 2) - G(2, 0)), 0.5 * (G(1, 0) - G(0, 1)));
        for (PetscInt v : cell.vertex) {
          for (int i = 0; i < 3; ++i) sum[4 * v + i] += cell.weight[p] * w[i];
          sum[4 * v + 3] += cell.weight[p];
        }
      }
    }
    PetscCall(VecRestoreArrayRead(dLocal, &d));
    PetscCall(VecRestoreArrayRead(xLocal, &x));
    PetscCall(sumOverSharedVertices(*mesh_, 4, &sum));
    for (size_t v = 0; v < verts_.size(); ++v)
      if (sum[4 * v + 3] > 0.0)
        for (int i = 0; i < 3; ++i) (*spin)[3 * v + i] = sum[4 * v + i] / sum[4 * v + 3];
  }
  PetscFunctionReturn(0);
}

template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::turnBySpin(const std::vector<double> &spin, Vec dLocal, double scale,
                                                 Vec outLocal) const {
  PetscFunctionBeginUser;
  PetscCall(VecAXPBY(outLocal, scale, 0.0, dLocal));
  if constexpr (R == 3) {
    const PetscScalar *d;
    PetscScalar *out;
    PetscCall(VecGetArrayRead(dLocal, &d));
    PetscCall(VecGetArray(outLocal, &out));
    for (size_t v = 0; v < verts_.size(); ++v) {
      const VertexInfo &vi = verts_[v];
      const Eigen::Vector3d w = scale * Eigen::Vector3d(spin[3 * v], spin[3 * v + 1], spin[3 * v + 2]);
      const double theta = w.norm();
      if (vi.bcSet >= 0 || theta < 1e-8) continue;
      const Eigen::Vector3d p = scale * Eigen::Vector3d(d[vi.loc], d[vi.loc + 1], d[vi.loc + 2]);
      const Eigen::Vector3d axis = w / theta;
      const Eigen::Vector3d pAxial = axis.dot(p) * axis, pPerp = p - pAxial;
      const Eigen::Vector3d rPerp = pPerp.cross(w) / (theta * theta);  // p_perp = w x r_perp
      const Eigen::Vector3d delta = pAxial + std::sin(theta) / theta * pPerp + (std::cos(theta) - 1.0) * rPerp;
      for (int i = 0; i < 3; ++i) out[vi.loc + i] = delta[i];
    }
    PetscCall(VecRestoreArray(outLocal, &out));
    PetscCall(VecRestoreArrayRead(dLocal, &d));
  }
  PetscFunctionReturn(0);
}

template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::ownedVertexValues(Vec local, std::vector<double> *values) const {
  const PetscScalar *a;
  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(local, &a));
  ownedVertexRows(3, [&](size_t v, double *out) {
    for (int i = 0; i < 3; ++i) out[i] = i < R ? a[verts_[v].loc + i] : 0.0;
  }, values);
  PetscCall(VecRestoreArrayRead(local, &a));
  PetscFunctionReturn(0);
}

template <int R, int C, int NV>
void DiscretizationT<R, C, NV>::ownedRestPositions(std::vector<double> *values) const {
  ownedVertexRows(3, [&](size_t v, double *out) {
    for (int i = 0; i < 3; ++i) out[i] = verts_[v].rest[i];
  }, values);
}

template <int R, int C, int NV>
void DiscretizationT<R, C, NV>::ownedCellValues(const std::vector<double> &perCell, int components,
                                            std::vector<double> *values) const {
  values->clear();
  for (size_t c = 0; c < cells_.size(); ++c)
    if (cells_.cells()[c].owned)
      values->insert(values->end(), perCell.begin() + c * components, perCell.begin() + (c + 1) * components);
}

template <int R, int C, int NV>
void DiscretizationT<R, C, NV>::ownedTopology(std::vector<PetscInt> *cellsOut) const {
  cellsOut->clear();
  for (size_t c = 0; c < cells_.size(); ++c) {
    const Cell &cell = cells_.cells()[c];
    if (!cell.owned) continue;
    for (int v = 0; v < NV; ++v)  // in the order of the element type's output topology
      cellsOut->push_back(mesh_->naturalVertex[cell.vertex[Element::outputNode(v)]]);
  }
}

template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::cellFibers(std::vector<double> *fibers) const {
  PetscFunctionBeginUser;
  fibers->clear();
  for (const auto &f : restFibers_) fibers->insert(fibers->end(), f.begin(), f.end());
  PetscFunctionReturn(0);
}

// Every cell whose data can differ is checked (fibers, targets, caricature curvature; with data shared by all cells,
// one cell per region): at its rest deformation gradient the stretch terms must be stationary (a caricature's I4 term
// is not: its minimum is a stretch along n) with a Hessian whose only zero eigenvalues are the three rotations' and
// none negative.
template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::stretchTermsFixShape(bool *fixes) const {
  PetscFunctionBeginUser;
  int ok = R == 3 && C == 3;
  if constexpr (R == 3 && C == 3) {
    std::vector<char> regionChecked(materials_.size(), 0);
    for (size_t c = 0; c < cells_.size() && ok; ++c) {
      const int region = cells_.cells()[c].region;
      if (cells_.dataShared() && regionChecked[region]) continue;
      regionChecked[region] = 1;
      energies::Material m = cells_.materialOf(c);
      m.lambda = 0.0;
      const energies::CellData<3> &data = cells_.dataOf(c);
      const kernels::Mat<3, 3> rest =
          m.kind == energies::EnergyKind::ShapeTarget ? data.target : kernels::Mat<3, 3>::Identity();
      const kernels::Derivs<9> d = energies::evaluateEnergy<3, 3>(m, data, rest);
      const kernels::Vec<9> ev = kernels::symmetricEigenvalues<9>(d.hess);  // ascending
      const double tol = 1e-8 * ev.cwiseAbs().maxCoeff();
      ok = ev(0) >= -tol && ev(3) > tol && d.grad.cwiseAbs().maxCoeff() <= tol;
    }
  }
  int all = 0;
  PetscCallMPI(MPI_Allreduce(&ok, &all, 1, MPI_INT, MPI_MIN, comm()));
  *fixes = all != 0;
  PetscFunctionReturn(0);
}

ARIES_INSTANTIATE_FOR_ELEMENT_TYPES(DiscretizationT)

}  // namespace aries::fem
