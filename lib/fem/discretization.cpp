#include "fem/discretization_impl.hpp"
#include "kernels/dense_decompositions.hpp"

#include <petscdmplex.h>

#include <algorithm>
#include <type_traits>
#include <cmath>

namespace aries::fem {

double Discretization::characteristicModulus() const {
  double m = 0.0;
  for (const auto &mat : materials_)
    m = std::max({m, mat.mu, mat.mu1, mat.mu2, mat.weight3.trace() / 3.0, mat.lambda});
  return m > 0.0 ? m : 1.0;
}

// What elements other than linear simplices do not have yet: the caricature field (its curvature comes from the linear
// tet mesh's boundary triangles). One line naming the option, before any work.
template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::refuseOnPointRules(const Mesh &mesh, const FemOptions &o) const {
  PetscFunctionBeginUser;
  const char *has = Element::kMeshHas;
  for (const MaterialOptions &m : o.materials)
    if (energies::energyCellField(m.material.kind) == energies::CellField::SurfaceCurvature)
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
              "option -energy %s: the caricature's curvature field needs linear tetrahedra (mesh '%s' %s)",
              energies::energyName(m.material.kind), mesh.filename.c_str(), has);
  PetscFunctionReturn(0);
}

template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::setup(Mesh &mesh, const FemOptions &o, double dt) {
  PetscFunctionBeginUser;
  mesh_ = &mesh;
  dofs_ = R;
  if constexpr (!Element::kLinearSimplex) PetscCall(refuseOnPointRules(mesh, o));
  std::vector<UniformCellData> regionCells;
  std::vector<std::pair<DMLabel, PetscInt>> regionLabels;  // (label, value) marking each region's cells
  for (const MaterialOptions &m : o.materials) {
    materials_.push_back(m.material);
    regionCells.push_back(m.cell);
    if (m.region.empty()) continue;
    DMLabel label;
    PetscInt value;
    PetscCall(regionLabel(mesh, m.region, &label, &value));
    regionLabels.emplace_back(label, value);
  }
  dyn_ = o.dynamics;
  bc_ = o.boundary;
  std::vector<Eigen::Vector3d> rest;
  PetscCall(vertexRestPositions(mesh, &rest));
  std::vector<PetscInt> bcFlag;
  PetscCall(markDirichlet(mesh, rest, &bcFlag));
  PetscCall(layoutDofs(mesh, rest, bcFlag));
  PetscCall(setupRestCells(mesh, regionLabels));
  PetscCall(setupCellData(mesh, o, regionCells, !regionLabels.empty()));
  PetscCall(setupMass(mesh));
  PetscCall(setupTerms(mesh, o, dt));
  PetscFunctionReturn(0);
}

// The body without its supports (the detached start): this discretization's materials, rest cells, cell data (fibers,
// regions, the per-cell fields at the current step) and mass, copied rather than read or computed again;
// the DOF layout on `mesh`'s DM (a DMClone of this one's: the same local cells and vertices) with every vertex free;
// the elastic terms (and cloth bending) with no gravity, contact or surface loads. The barrier's fallback cells are not carried
// over: the detached body is evaluated as read.
template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::detachedCopy(Mesh &mesh, std::unique_ptr<Discretization> *out) const {
  PetscInt pStart, pEnd;
  PetscFunctionBeginUser;
  auto d = std::make_unique<DiscretizationT<R, C, NV>>();
  d->mesh_ = &mesh;
  d->dofs_ = R;
  d->bc_ = bc_;
  d->restMeasure_ = restMeasure_;
  d->materials_ = materials_;
  d->dyn_ = dyn_;
  d->dyn_.gravity.setZero();
  d->hessianFilter_ = hessianFilter_;
  d->wholeElementFilter_ = wholeElementFilter_;
  d->step_ = step_;
  std::vector<Eigen::Vector3d> rest(verts_.size());
  for (size_t v = 0; v < verts_.size(); ++v) rest[v] = verts_[v].rest;
  PetscCall(DMPlexGetChart(mesh.dm, &pStart, &pEnd));
  PetscCall(d->layoutDofs(mesh, rest, std::vector<PetscInt>(3 * (pEnd - pStart), PETSC_MAX_INT)));
  d->cells_.cells() = cells_.cells();
  d->cells_.cellData() = cells_.cellData();
  d->restFibers_ = restFibers_;
  d->fields_ = fields_.copy();
  d->mass_ = mass_;
  d->gravityMass_ = gravityMass_;
  d->keepOrientation_ = keepOrientation_;
  d->terms_ = {&d->cells_};
  if (hinges_) PetscCall(d->addBendingHinges(mesh, hinges_->stiffness()));
  PetscCall(d->addInertiaGravity(mesh));
  *out = std::move(d);
  PetscFunctionReturn(0);
}

template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::addBendingHinges(Mesh &mesh, double stiffness) {
  PetscFunctionBeginUser;
  hinges_ = std::make_unique<BendingHinges>(verts_, stiffness);
  const auto opposite = [&](PetscInt cell, PetscInt v0, PetscInt v1) {
    PetscInt o = -1;
    for (PetscInt v : cells_.cells()[cell - mesh.cStart].vertex)
      if (v != v0 && v != v1) o = v;
    return o;
  };
  PetscCall(hinges_->build(mesh.dm, mesh.vStart, opposite));
  terms_.push_back(hinges_.get());
  PetscFunctionReturn(0);
}

template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::addInertiaGravity(const Mesh &mesh) {
  PetscSection localSection;
  PetscInt localSize;
  PetscFunctionBeginUser;
  PetscCall(DMGetLocalSection(mesh.dm, &localSection));
  PetscCall(PetscSectionGetStorageSize(localSection, &localSize));
  inertia_ = std::make_unique<InertiaGravity<R>>(verts_, mass_, gravityMass_, dyn_.gravity, localSize);
  terms_.push_back(inertia_.get());
  PetscFunctionReturn(0);
}

// The terms of the total potential, in assembly order: elastic cells, cloth bending hinges (-bending, surfaces in
// 3D), contact with analytic obstacles (3D meshes), inertia and gravity, surface loads.
template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::setupTerms(Mesh &mesh, const FemOptions &o, double dt) {
  PetscFunctionBeginUser;
  terms_ = {&cells_};
  keepOrientation_ = o.keepOrientation ? PETSC_TRUE : PETSC_FALSE;
  if (o.bending > 0.0) PetscCall(addBendingHinges(mesh, o.bending));
  if constexpr (R == 3) {
    // Default contact stiffness: the body's own stiffness at a vertex, so contact neither lets vertices sink deep
    // into the barrier's log singularity (slow Newton at impacts) nor dominates the system: with inertia the mean
    // vertex mass / dt^2; quasistatic, modulus * h^(dim - 2) with h = (measure / vertices)^(1/dim) the mean vertex
    // spacing (dim = 2 for surfaces, 3 for solids).
    const double perVertex = restMeasure_ / static_cast<double>(mesh.numVerticesGlobal);
    const double stiffness = dt > 0.0 ? dyn_.density * perVertex / (dt * dt)
                                      : characteristicModulus() * std::pow(perVertex, 1.0 - 2.0 / C);
    contact_ = std::make_unique<ObstacleContact>(verts_);
    PetscCall(contact_->setup(mesh, o.contact, stiffness));
    if (!contact_->empty()) terms_.push_back(contact_.get());
  }
  PetscCall(addInertiaGravity(mesh));
  if (!o.loads.empty()) {
    loads_ = std::make_unique<SurfaceLoads<R>>(verts_);
    PetscCall(loads_->setup(mesh, o.loads));
    loads_->setLoad(step_.load);
    if (!loads_->empty()) terms_.push_back(loads_.get());
    if constexpr (!std::is_void_v<typename Element::Face>) {  // a volume element: pressure on its faces
      pressure_ = std::make_unique<FollowerPressure<PressureFaceOf<Element>>>(verts_);
      PetscCall(pressure_->setup(mesh, o.loads));
      pressure_->setLoad(step_.load);
      if (!pressure_->empty()) terms_.push_back(pressure_.get());
    }
  }
  PetscFunctionReturn(0);
}

template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::setStep(const StepState &step) {
  PetscFunctionBeginUser;
  const bool moved = step.load != step_.load || step.time != step_.time;
  step_ = step;
  step_.prediction = nullptr;  // the stepper's vector: copied below, never kept
  if (moved && fields_.varies()) fields_.update(step_.time, step_.load, &cells_.cellData());
  inertia_->setTimeStep(step.dt);
  if (loads_) loads_->setLoad(step.load);
  if (pressure_) pressure_->setLoad(step.load);
  if (step.dt > 0.0 && step.prediction) {  // kept until a step brings a new one
    Vec loc;
    const PetscScalar *x;
    std::vector<double> &prediction = inertia_->prediction();
    PetscCall(DMGetLocalVector(mesh_->dm, &loc));
    PetscCall(DMGlobalToLocal(mesh_->dm, step.prediction, INSERT_VALUES, loc));
    PetscCall(VecGetArrayRead(loc, &x));
    std::copy(x, x + prediction.size(), prediction.begin());
    PetscCall(VecRestoreArrayRead(loc, &x));
    PetscCall(DMRestoreLocalVector(mesh_->dm, &loc));
  }
  PetscFunctionReturn(0);
}

template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::fillBoundary(Vec xLocal, double load) const {
  PetscScalar *x;
  PetscFunctionBeginUser;
  PetscCall(VecGetArray(xLocal, &x));
  for (const auto &vi : verts_)
    for (int i = 0; i < R; ++i)
      if (vi.fixed(i)) x[vi.loc + i] = bc_.sets[vi.fixedBy[i]].target(vi.rest, load)[i];
  PetscCall(VecRestoreArray(xLocal, &x));
  PetscFunctionReturn(0);
}

template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::restPositions(Vec xGlobal) const {
  PetscScalar *x;
  PetscInt lo;
  PetscFunctionBeginUser;
  PetscCall(VecGetOwnershipRange(xGlobal, &lo, nullptr));
  PetscCall(VecGetArray(xGlobal, &x));
  for (const auto &vi : verts_)
    if (vi.owned)
      for (int i = 0; i < R; ++i)
        if (!vi.fixed(i)) x[vi.row(i) - lo] = vi.rest[i];
  PetscCall(VecRestoreArray(xGlobal, &x));
  PetscFunctionReturn(0);
}

template <int R, int C, int NV>
void DiscretizationT<R, C, NV>::forEachOwnedFreeVertex(
    const std::function<void(PetscInt, PetscInt, const PetscInt *, const Eigen::Vector3d &)> &fn) const {
  for (size_t v = 0; v < verts_.size(); ++v) {
    const auto &vi = verts_[v];
    if (!vi.ownedFree()) continue;
    const PetscInt rows[3] = {vi.row(0), vi.row(1), R == 3 ? vi.row(2) : -1};
    fn(static_cast<PetscInt>(v), mesh_->naturalVertex[v], rows, vi.rest);
  }
}

template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::lumpedMass(Vec massGlobal) const {
  PetscScalar *m;
  PetscInt lo;
  PetscFunctionBeginUser;
  PetscCall(VecGetOwnershipRange(massGlobal, &lo, nullptr));
  PetscCall(VecGetArray(massGlobal, &m));
  for (size_t v = 0; v < verts_.size(); ++v) {
    const auto &vi = verts_[v];
    if (vi.owned)
      for (int i = 0; i < R; ++i)
        if (!vi.fixed(i)) m[vi.row(i) - lo] = mass_[v];
  }
  PetscCall(VecRestoreArray(massGlobal, &m));
  PetscFunctionReturn(0);
}

template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::vertexPositions(Vec xLocal, std::vector<double> *xyz) const {
  const PetscScalar *x;
  PetscFunctionBeginUser;
  xyz->assign(3 * verts_.size(), 0.0);
  PetscCall(VecGetArrayRead(xLocal, &x));
  for (size_t v = 0; v < verts_.size(); ++v)
    for (int i = 0; i < R; ++i) (*xyz)[3 * v + i] = x[verts_[v].loc + i];
  PetscCall(VecRestoreArrayRead(xLocal, &x));
  PetscFunctionReturn(0);
}

template <int R, int C, int NV>
void DiscretizationT<R, C, NV>::ownedSupportedVertices(std::vector<PetscInt> *local) const {
  local->clear();
  for (size_t v = 0; v < verts_.size(); ++v)
    if (verts_[v].owned && verts_[v].bcSet >= 0 && verts_[v].numFree == 0) local->push_back(static_cast<PetscInt>(v));
}

// The rigid motions' values at the prescribed components span a space of dimension 6 - count: the rank of their
// Gram matrix (sum over every owned vertex's prescribed components of m_k m_l, the rest positions taken about the
// prescribed points' centroid in units of the body's diagonal, so that translations and rotations weigh alike).
template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::freeRigidMotions(PetscInt *count) const {
  constexpr int n = R == 3 ? 6 : 3;  // translations, then rotations (about x, y, z; planar: about z)
  MPI_Comm comm = PetscObjectComm((PetscObject)mesh_->dm);
  PetscFunctionBeginUser;
  double centroid[4] = {0.0, 0.0, 0.0, 0.0};  // count, sum of positions
  for (const VertexInfo &vi : verts_)
    for (int i = 0; vi.owned && i < R; ++i)
      if (vi.fixed(i)) {
        centroid[0] += 1.0;
        for (int a = 0; a < 3; ++a) centroid[1 + a] += vi.rest[a];
      }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, centroid, 4, MPI_DOUBLE, MPI_SUM, comm));
  *count = n;
  if (centroid[0] == 0.0) PetscFunctionReturn(0);
  const Eigen::Vector3d c = Eigen::Vector3d(centroid[1], centroid[2], centroid[3]) / centroid[0];
  const double scale = mesh_->diagonal > 0.0 ? 1.0 / mesh_->diagonal : 1.0;
  Eigen::Matrix<double, n, n> gram = Eigen::Matrix<double, n, n>::Zero();
  for (const VertexInfo &vi : verts_)
    for (int i = 0; vi.owned && i < R; ++i) {
      if (!vi.fixed(i)) continue;
      const Eigen::Vector3d X = (vi.rest - c) * scale;
      Eigen::Matrix<double, n, 1> m;  // each mode's component i at X
      for (int k = 0; k < n; ++k) m[k] = rigidMotion(k, R, X)[i];
      gram += m * m.transpose();
    }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, gram.data(), n * n, MPI_DOUBLE, MPI_SUM, comm));
  const kernels::Vec<n> eigenvalues = kernels::symmetricEigenvalues<n>(gram);
  const double largest = eigenvalues.maxCoeff();
  *count = 0;
  for (int k = 0; k < n; ++k) *count += eigenvalues[k] <= 1e-10 * largest;
  PetscFunctionReturn(0);
}

ARIES_INSTANTIATE_FOR_ELEMENT_TYPES(DiscretizationT)

bool Discretization::suspendVolumeTerms(bool suspend) {
  bool changed = false;
  if (suspend && lambdaRead_.empty()) {
    for (energies::Material &m : materials_) {
      lambdaRead_.push_back(m.lambda);
      if (energies::energyUsesVolumeTerm(m.kind) && m.lambda != 0.0) {
        m.lambda = 0.0;
        changed = true;
      }
    }
    if (!changed) lambdaRead_.clear();
  } else if (!suspend && !lambdaRead_.empty()) {
    for (size_t r = 0; r < materials_.size(); ++r) {
      changed = changed || materials_[r].lambda != lambdaRead_[r];
      materials_[r].lambda = lambdaRead_[r];
    }
    lambdaRead_.clear();
  }
  return changed;
}

// The registered element type that runs on the mesh (fem/element_types.hpp): exactly one fits each mesh kind the
// loader accepts.
PetscErrorCode Discretization::create(Mesh &mesh, const FemOptions &options, double dt,
                                      std::unique_ptr<Discretization> *out) {
  PetscFunctionBeginUser;
  out->reset();
#define ARIES_CREATE_IF_FITS(E, unused)                                 \
  if (!*out && elementFitsMesh<E>(mesh)) {                              \
    auto d = std::make_unique<DiscretizationT<E::R, E::C, E::NV>>();    \
    PetscCall(d->setup(mesh, options, dt));                             \
    *out = std::move(d);                                                \
  }
  ARIES_ELEMENT_TYPES(ARIES_CREATE_IF_FITS, )
#undef ARIES_CREATE_IF_FITS
  PetscCheck(*out, PETSC_COMM_SELF, PETSC_ERR_SUP, "mesh '%s': no element type runs on its cells",
             mesh.filename.c_str());
  PetscFunctionReturn(0);
}

}  // namespace aries::fem
