#include "fem/discretization.hpp"

#include "energies/energy.hpp"
#include "fem/cell_files.hpp"
#include "fem/options.hpp"
#include "fem/caricature_field.hpp"
#include "fem/shape_targets.hpp"
#include "kernels/obstacle_barrier.hpp"
#include "kernels/quadratic_bending.hpp"
#include "fem/errors.hpp"

#include <petscsf.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <sstream>

namespace aries::fem {

using energies::ElementShape;
template <int Rr, int Cc>
using EMat = kernels::Mat<Rr, Cc>;
template <int Nn>
using EVec = kernels::Vec<Nn>;

namespace {

// Gathers (natural id, values) pairs onto rank 0 into a dense array of `total * comps` values.
PetscErrorCode gatherNatural(MPI_Comm comm, const std::vector<PetscInt> &ids, const std::vector<double> &vals,
                             int comps, PetscInt total, std::vector<double> *out, bool sum = false) {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  std::vector<double> mine, all;  // per entry: id (exact as a double below 2^53), then its values
  mine.reserve(ids.size() * (comps + 1));
  for (size_t i = 0; i < ids.size(); ++i) {
    mine.push_back(static_cast<double>(ids[i]));
    mine.insert(mine.end(), vals.begin() + i * comps, vals.begin() + (i + 1) * comps);
  }
  PetscCall(gatherOnRoot(comm, mine, &all));
  out->clear();
  if (rank == 0) {
    out->assign(static_cast<size_t>(total) * comps, 0.0);
    for (size_t e = 0; e < all.size(); e += comps + 1) {
      double *dst = &(*out)[static_cast<size_t>(all[e]) * comps];
      for (int k = 0; k < comps; ++k) dst[k] = sum ? dst[k] + all[e + 1 + k] : all[e + 1 + k];
    }
  }
  PetscFunctionReturn(0);
}

// Matrix adjacency of a surface mesh with bending hinges (DMPlexSetAdjacencyUser): a hinge couples the two vertices
// opposite an interior edge, which share no triangle, so the default FEM adjacency (the closure of the star) misses
// them. Here adj(p) is the closure of every triangle in the star of p and of the triangles across their edges: exactly
// the hinge partners added, so DMCreateMatrix preallocates every coupling and assembly never mallocs.
PetscErrorCode hingeAdjacency(DM dm, PetscInt p, PetscInt *adjSize, PetscInt adj[], void *) {
  const PetscInt capacity = *adjSize;
  PetscInt n = 0, cStart, cEnd, nstar = 0, *star = nullptr;
  PetscFunctionBeginUser;
  const auto add = [&](PetscInt q) -> PetscErrorCode {
    PetscFunctionBeginUser;
    for (PetscInt i = 0; i < n; ++i)
      if (adj[i] == q) PetscFunctionReturn(0);
    PetscCheck(n < capacity, PETSC_COMM_SELF, PETSC_ERR_PLIB, "hinge adjacency of point %" PetscInt_FMT
               " exceeds DMPlex's bound of %" PetscInt_FMT " points", p, capacity);
    adj[n++] = q;
    PetscFunctionReturn(0);
  };
  const auto addClosure = [&](PetscInt cell) -> PetscErrorCode {
    PetscInt nclosure = 0, *closure = nullptr;
    PetscFunctionBeginUser;
    PetscCall(DMPlexGetTransitiveClosure(dm, cell, PETSC_TRUE, &nclosure, &closure));
    for (PetscInt i = 0; i < nclosure; ++i) PetscCall(add(closure[2 * i]));
    PetscCall(DMPlexRestoreTransitiveClosure(dm, cell, PETSC_TRUE, &nclosure, &closure));
    PetscFunctionReturn(0);
  };
  PetscCall(DMPlexGetHeightStratum(dm, 0, &cStart, &cEnd));
  PetscCall(DMPlexGetTransitiveClosure(dm, p, PETSC_FALSE, &nstar, &star));
  for (PetscInt i = 0; i < nstar; ++i) {
    const PetscInt t = star[2 * i];
    if (t < cStart || t >= cEnd) continue;
    PetscInt nedges;
    const PetscInt *edges;
    PetscCall(DMPlexGetConeSize(dm, t, &nedges));
    PetscCall(DMPlexGetCone(dm, t, &edges));
    for (PetscInt e = 0; e < nedges; ++e) {
      PetscInt nsupp;
      const PetscInt *supp;
      PetscCall(DMPlexGetSupportSize(dm, edges[e], &nsupp));
      PetscCall(DMPlexGetSupport(dm, edges[e], &supp));
      for (PetscInt k = 0; k < nsupp; ++k) PetscCall(addClosure(supp[k]));
    }
  }
  PetscCall(DMPlexRestoreTransitiveClosure(dm, p, PETSC_FALSE, &nstar, &star));
  *adjSize = n;
  PetscFunctionReturn(0);
}

// Material frame of a rest triangle in 3D with (oriented) unit normal n: the projection of the global x and y axes
// onto its plane (a flat cloth in the xy plane with normals +z has u = x, v = y); falls back to (x,z) / (y,z). The
// frame is made right-handed about n, so every rest triangle of a consistently oriented surface has a positive
// area in it (and a flipped element of a UV map is one with det F < 0).
Eigen::Matrix<double, 3, 2> orientedFrame(Eigen::Matrix<double, 3, 2> E, const Eigen::Vector3d &n) {
  if (E.col(0).cross(E.col(1)).dot(n) < 0.0) E.col(1) *= -1.0;
  return E;
}

Eigen::Matrix<double, 3, 2> clothFrame(const Eigen::Vector3d &n) {
  const Eigen::Vector3d axes[3] = {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ()};
  const int pairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  for (const auto &p : pairs) {
    Eigen::Vector3d e1 = axes[p[0]] - n.dot(axes[p[0]]) * n;
    if (e1.norm() < 0.3) continue;
    e1.normalize();
    Eigen::Vector3d e2 = axes[p[1]] - n.dot(axes[p[1]]) * n;
    e2 -= e1.dot(e2) * e1;
    if (e2.norm() < 0.3) continue;
    Eigen::Matrix<double, 3, 2> E;
    E << e1, e2.normalized();
    return orientedFrame(E, n);
  }
  Eigen::Matrix<double, 3, 2> E;
  E << n.unitOrthogonal(), n.cross(n.unitOrthogonal());
  return orientedFrame(E, n);
}

}  // namespace

double Discretization::characteristicModulus() const {
  double m = 0.0;
  for (const auto &mat : materials_)
    m = std::max({m, mat.mu, mat.mu1, mat.mu2, mat.weight3.trace() / 3.0, mat.lambda});
  return m > 0.0 ? m : 1.0;
}

template <int R, int C>
class DiscretizationT final : public Discretization {
 public:
  static constexpr int NV = C + 1;
  static constexpr int NDOF = NV * R;
  static constexpr int NF = R * C;

  PetscErrorCode setup(Mesh &mesh, double dt);

  PetscErrorCode setLoad(double s) override {
    PetscFunctionBeginUser;
    load_ = s;
    if (targets_.loadDependent()) updateTargets();
    PetscFunctionReturn(0);
  }
  PetscErrorCode setTime(double t) override {
    PetscFunctionBeginUser;
    time_ = t;
    if (targets_.timeDependent()) updateTargets();
    PetscFunctionReturn(0);
  }
  PetscErrorCode fillBoundary(Vec xLocal) const override;
  PetscErrorCode restPositions(Vec xGlobal) const override;
  PetscErrorCode setPrediction(Vec xTildeGlobal) override;
  PetscErrorCode lumpedMass(Vec massGlobal) const override;
  PetscErrorCode objective(Vec xLocal, PetscReal *value, PetscReal *magnitude = nullptr) const override;
  PetscErrorCode gradient(Vec xLocal, Vec gLocal) const override;
  PetscErrorCode hessian(Vec xLocal, Mat J) override;
  PetscErrorCode curvatureGram(Vec xLocal, const std::vector<Vec> &dLocal, std::vector<double> *gram) const override;
  PetscErrorCode elasticEnergy(Vec xLocal, PetscReal *value) const override;
  PetscErrorCode updateBarrierFallback(Vec xLocal, double threshold, PetscInt *count) override;
  PetscErrorCode cellAlpha(Vec xLocal, std::vector<double> *alpha) const override;
  PetscErrorCode cellGuard(Vec xLocal, std::vector<double> *guard) const override;
  PetscErrorCode cellQuantities(Vec xLocal, CellQuantities *q) const override;
  PetscErrorCode barrierActiveCells(Vec xLocal, PetscInt *count) const override {
    const PetscScalar *x;
    MPI_Comm comm;
    PetscFunctionBeginUser;
    PetscCall(PetscObjectGetComm((PetscObject)mesh_->dm, &comm));
    PetscInt local = 0;
    PetscCall(VecGetArrayRead(xLocal, &x));
    for (size_t c = 0; c < cells_.size(); ++c) {
      const energies::Material &m = materialOf(c);
      if (!cells_[c].owned || m.singularity.mode != energies::SingularityMode::Barrier ||
          !energies::energyContainsStretchInvariant(m.kind))
        continue;
      const double a = energies::elementAlpha<R, C>(deformationGradient(cells_[c], x));
      local += a > 0.0 && a < m.singularity.barrier.eps;
    }
    PetscCall(VecRestoreArrayRead(xLocal, &x));
    PetscCallMPI(MPI_Allreduce(&local, count, 1, MPIU_INT, MPI_SUM, comm));
    PetscFunctionReturn(0);
  }
  void mollifierBandTop(std::vector<double> *top) const override {
    top->resize(cells_.size());
    for (size_t c = 0; c < cells_.size(); ++c) {
      const energies::Material &m = materialOf(c);
      const bool mollified = m.singularity.mode == energies::SingularityMode::Mollifier &&
                             energies::energyContainsStretchInvariant(m.kind);
      (*top)[c] = mollified ? m.singularity.mollifier.eps : 0.0;
    }
  }
  PetscErrorCode gatherVertexField(Vec xLocal, std::vector<double> *values) const override;
  PetscErrorCode gatherRestPositions(std::vector<double> *values) const override;
  PetscErrorCode gatherCellField(const std::vector<double> &perCell, int components,
                                 std::vector<double> *values) const override;
  PetscErrorCode gatherTopology(std::vector<PetscInt> *cells) const override;
  PetscErrorCode cellFibers(std::vector<double> *fibers) const override;
  int shapeCols() const override { return C; }
  void forEachOwnedFreeVertex(
      const std::function<void(PetscInt, PetscInt, PetscInt, const Eigen::Vector3d &)> &fn) const override;
  PetscErrorCode maxDisplacement(Vec xLocal, PetscReal *value) const override;
  PetscErrorCode reactionForce(Vec xLocal, size_t set, Eigen::Vector3d *force) const override;
  PetscErrorCode cellStressMeasures(Vec xLocal, std::vector<kernels::StressMeasures> *out) const override;
  void cellRegions(std::vector<double> *regions) const override;
  PetscErrorCode gatherVertexReactions(Vec xLocal, std::vector<double> *values) const override;
  PetscErrorCode gatherVertexMarkers(std::vector<double> *values) const override;

 private:
  struct Cell {
    std::array<PetscInt, NV> vertex;  // local vertex index (v - vStart)
    EMat<NV, C> W;                     // F = sum_v x_v W.row(v)   (W = [-1^T Dm^-1; Dm^-1])
    double measure;                   // rest volume / area
    int region;                       // material index
    bool owned;                       // false for overlap cells (surface meshes), skipped by all sums
  };
  struct Hinge {                      // bending hinge: edge (v0, v1), opposite vertices v2, v3 (local indices)
    std::array<PetscInt, 4> vertex;
    kernels::BendingHinge rest;
  };
  struct VertexInfo {
    PetscInt loc;     // offset of the first dof in the local vector
    PetscInt global;  // offset of the first dof in the global vector (-1 if Dirichlet); for owned only meaningful
    bool owned;
    int bcSet;        // index into bc_.sets, -1 if free
    Eigen::Vector3d rest;
  };

  // A local vector's vertex values (padded to 3 components) gathered in natural order on rank 0, for the vertices
  // `include` selects: each vertex's value taken once from its owner, or (sumShares) every rank's value summed.
  PetscErrorCode gatherLocalVertexValues(Vec local, const std::function<bool(const VertexInfo &)> &include,
                                         bool sumShares, std::vector<double> *values) const;
  EMat<R, C> deformationGradient(const Cell &cell, const PetscScalar *x) const {
    EMat<R, C> F = EMat<R, C>::Zero();
    for (int v = 0; v < NV; ++v) {
      const PetscScalar *xv = x + verts_[cell.vertex[v]].loc;
      for (int i = 0; i < R; ++i) F.row(i) += xv[i] * cell.W.row(v);
    }
    return F;
  }
  const energies::CellData<C> &dataOf(size_t c) const { return cellData_.size() == 1 ? cellData_[0] : cellData_[c]; }
  const energies::Material &materialOf(size_t c) const {
    return fallback_.empty() || !fallback_[c] ? materials_[cells_[c].region] : mollified_[cells_[c].region];
  }
  // Energy sums on this rank; `magnitude` (optional) accumulates the absolute values of the terms.
  PetscErrorCode vertexTermsObjective(const PetscScalar *x, double *E, double *magnitude = nullptr) const;
  double cellEnergySum(const PetscScalar *x, double *magnitude = nullptr) const;  // owned cells
  double surfaceTermsEnergy(const PetscScalar *x, double *magnitude = nullptr) const;  // bending + contact
  void addSurfaceTermsGradient(const PetscScalar *x, PetscScalar *g) const;
  PetscErrorCode addSurfaceTermsHessian(const PetscScalar *x, Mat J) const;
  PetscErrorCode setupSurfaceTerms(Mesh &mesh, double dt);
  bool usesEnergy(energies::EnergyKind kind) const;  // by any region
  PetscErrorCode setupActiveMaterials(Mesh &mesh);
  void updateTargets();

  std::vector<Cell> cells_;
  std::vector<VertexInfo> verts_;
  std::vector<energies::CellData<C>> cellData_;
  std::vector<std::array<double, 3>> restFibers_;  // per cell, for output (material frame)
  TargetField targets_;                            // shape_target: -activation / -target_file
  std::vector<double> mass_;                       // per local vertex
  std::vector<double> xTilde_;                     // per local dof (dynamics)
  std::vector<Hinge> hinges_;                      // owned interior edges (cloth bending)
  PetscBool keepOrientation_ = PETSC_FALSE;        // -keep_orientation (planar elements)
  double bending_ = 0.0;                           // -bending stiffness
  std::vector<kernels::Obstacle> obstacles_;       // -obstacle_plane / -obstacle_sphere
  double contactDhat_ = 0.0, contactKappa_ = 0.0;  // -contact_dhat, -contact_stiffness
  std::vector<char> fallback_;                     // per cell: barrier -> mollifier (singular elements)
  std::vector<energies::Material> mollified_;      // materials_ with the barrier replaced by the mollifier
  bool blockedAssembly_ = true;
  bool stashSized_ = false;  // the off-rank assembly buffer sized before the first Hessian assembly
};

template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::setup(Mesh &mesh, double dt) {
  MPI_Comm comm;
  PetscFunctionBeginUser;
  mesh_ = &mesh;
  dofs_ = R;
  DM dm = mesh.dm;
  PetscCall(PetscObjectGetComm((PetscObject)dm, &comm));
  const ElementShape shape = mesh.shape;

  // --- materials: global + -regions ----------------------------------------------------------------------------
  energies::Material base;
  UniformCellData baseCell;
  PetscCall(readMaterialOptions(nullptr, shape, nullptr, nullptr, &base, &baseCell));
  materials_.push_back(base);
  std::vector<UniformCellData> regionCells{baseCell};
  std::vector<std::string> regionIds;
  PetscBool set = PETSC_FALSE;
  PetscCall(optionWordList(nullptr, "-regions", &regionIds, &set));
  std::vector<std::pair<DMLabel, PetscInt>> regionLabels;  // (label, value) marking each region's cells
  for (const auto &rid : regionIds) {
    DMLabel label;
    PetscInt value;
    PetscCall(regionLabel(mesh, rid, &label, &value));
    const std::string prefix = "region_" + rid + "_";
    energies::Material m;
    UniformCellData uc;
    PetscCall(readMaterialOptions(prefix.c_str(), shape, &base, &baseCell, &m, &uc));
    materials_.push_back(m);
    regionCells.push_back(uc);
    regionLabels.emplace_back(label, value);
  }

  // --- dynamics parameters ---------------------------------------------------------------------------------------
  PetscCall(optionReal(nullptr, "-density", &dyn_.density, &set));
  if (set && !(dyn_.density > 0.0))
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -density must be > 0 (got %g)", dyn_.density);
  std::vector<PetscReal> g;
  PetscCall(optionRealList(nullptr, "-gravity", &g, &set, R, 3));
  if (set) {
    for (size_t k = 0; k < g.size(); ++k) dyn_.gravity[k] = g[k];
    if (R == 2 && g.size() == 3 && g[2] != 0.0)
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -gravity: a 2D mesh takes gx,gy (z must be 0)");
  }

  // --- Dirichlet vertices --------------------------------------------------------------------------------------------
  PetscCall(readBoundaryOptions(&bc_));
  PetscInt pStart, pEnd;
  PetscCall(DMPlexGetChart(dm, &pStart, &pEnd));
  const PetscInt nv = mesh.vEnd - mesh.vStart;
  std::vector<PetscInt> bcFlag(pEnd - pStart, PETSC_MAX_INT);
  for (size_t s = 0; s < bc_.numGroups(); ++s) {
    std::vector<PetscInt> vs;
    bool found = false;
    PetscCall(physicalGroupVertices(mesh, bc_.sets[s].id, &vs, &found));
    if (!found) {
      std::string known;
      PetscCall(describePhysicalGroups(mesh, &known));
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
              "option -bc_clamp: boundary set '%s' does not exist in mesh '%s' (physical groups present: %s)",
              bc_.sets[s].id.c_str(), mesh.filename.c_str(), known.c_str());
    }
    for (PetscInt v : vs) bcFlag[v - pStart] = std::min<PetscInt>(bcFlag[v - pStart], static_cast<PetscInt>(s));
  }
  Vec coordsLocal;
  PetscSection coordSection;
  const PetscScalar *coords;
  PetscCall(DMGetCoordinatesLocal(dm, &coordsLocal));
  PetscCall(DMGetCoordinateSection(dm, &coordSection));
  PetscCall(VecGetArrayRead(coordsLocal, &coords));
  auto restOf = [&](PetscInt v) {
    PetscInt off;
    PetscSectionGetOffset(coordSection, v, &off);
    Eigen::Vector3d X = Eigen::Vector3d::Zero();
    for (int d = 0; d < mesh.spaceDim; ++d) X[d] = coords[off + d];
    return X;
  };
  for (size_t b = 0; b < bc_.boxes.size(); ++b) {
    const auto &bb = bc_.boxes[b];
    for (PetscInt v = mesh.vStart; v < mesh.vEnd; ++v) {
      const Eigen::Vector3d X = restOf(v);
      if (X[0] >= bb[0] && X[0] <= bb[1] && X[1] >= bb[2] && X[1] <= bb[3] && X[2] >= bb[4] && X[2] <= bb[5])
        bcFlag[v - pStart] = std::min<PetscInt>(bcFlag[v - pStart], static_cast<PetscInt>(bc_.numGroups() + b));
    }
  }
  // Shared vertices: every copy must agree (a boundary face may live on one rank only).
  PetscSF pointSF;
  PetscCall(DMGetPointSF(dm, &pointSF));
  {
    std::vector<PetscInt> root(bcFlag);
    PetscCall(PetscSFReduceBegin(pointSF, MPIU_INT, bcFlag.data(), root.data(), MPI_MIN));
    PetscCall(PetscSFReduceEnd(pointSF, MPIU_INT, bcFlag.data(), root.data(), MPI_MIN));
    PetscCall(PetscSFBcastBegin(pointSF, MPIU_INT, root.data(), bcFlag.data(), MPI_REPLACE));
    PetscCall(PetscSFBcastEnd(pointSF, MPIU_INT, root.data(), bcFlag.data(), MPI_REPLACE));
    for (PetscInt p = pStart; p < pEnd; ++p) bcFlag[p - pStart] = std::min(bcFlag[p - pStart], root[p - pStart]);
  }
  std::vector<char> sharedCopy;  // copies of another rank's points (leaves of the point SF)
  PetscCall(sharedLeafPoints(dm, &sharedCopy));

  // --- section with all components of Dirichlet vertices constrained ---------------------------------------------
  PetscSection section;
  PetscCall(PetscSectionCreate(comm, &section));
  PetscCall(PetscSectionSetNumFields(section, 1));
  PetscCall(PetscSectionSetFieldComponents(section, 0, R));
  PetscCall(PetscSectionSetChart(section, pStart, pEnd));
  for (PetscInt v = mesh.vStart; v < mesh.vEnd; ++v) {
    PetscCall(PetscSectionSetDof(section, v, R));
    PetscCall(PetscSectionSetFieldDof(section, v, 0, R));
    if (bcFlag[v - pStart] != PETSC_MAX_INT) {
      PetscCall(PetscSectionSetConstraintDof(section, v, R));
      PetscCall(PetscSectionSetFieldConstraintDof(section, v, 0, R));
    }
  }
  PetscCall(PetscSectionSetUp(section));
  const PetscInt allComps[3] = {0, 1, 2};
  for (PetscInt v = mesh.vStart; v < mesh.vEnd; ++v)
    if (bcFlag[v - pStart] != PETSC_MAX_INT) {
      PetscCall(PetscSectionSetConstraintIndices(section, v, allComps));
      PetscCall(PetscSectionSetFieldConstraintIndices(section, v, 0, allComps));
    }
  PetscCall(DMSetLocalSection(dm, section));
  PetscCall(PetscSectionDestroy(&section));
  PetscCall(DMSetMatType(dm, MATBAIJ));
  PetscSection localSection, globalSection;
  PetscCall(DMGetLocalSection(dm, &localSection));
  PetscCall(DMGetGlobalSection(dm, &globalSection));

  verts_.resize(nv);
  PetscInt numBcOwned = 0;
  for (PetscInt v = mesh.vStart; v < mesh.vEnd; ++v) {
    VertexInfo &vi = verts_[v - mesh.vStart];
    PetscCall(PetscSectionGetOffset(localSection, v, &vi.loc));
    vi.owned = !sharedCopy[v - pStart];
    vi.bcSet = bcFlag[v - pStart] == PETSC_MAX_INT ? -1 : static_cast<int>(bcFlag[v - pStart]);
    vi.rest = restOf(v);
    vi.global = -1;
    if (vi.bcSet < 0) {
      PetscInt goff;
      PetscCall(PetscSectionGetOffset(globalSection, v, &goff));
      vi.global = goff >= 0 ? goff : -(goff + 1);
    } else if (vi.owned) {
      ++numBcOwned;
    }
  }
  PetscCallMPI(MPI_Allreduce(&numBcOwned, &numBcGlobal_, 1, MPIU_INT, MPI_SUM, comm));

  // Clamp centers default to the centroid of each set at rest (owned vertices, all ranks).
  for (size_t s = 0; s < bc_.sets.size(); ++s) {
    if (bc_.sets[s].centerGiven) continue;
    CentroidAccumulator acc;
    for (const auto &vi : verts_)
      if (vi.owned && vi.bcSet == static_cast<int>(s)) acc.add(vi.rest);
    Eigen::Vector3d center;
    double count;
    PetscCall(acc.reduce(comm, &center, &count));
    if (count > 0) bc_.sets[s].center = center;
  }

  // --- per-cell rest data --------------------------------------------------------------------------------------------
  const PetscInt nc = mesh.cEnd - mesh.cStart;
  cells_.resize(nc);
  std::vector<double> signedMeasure(nc);
  for (PetscInt c = mesh.cStart; c < mesh.cEnd; ++c) {
    Cell &cell = cells_[c - mesh.cStart];
    PetscInt ncl, *closure = nullptr, k = 0;
    PetscCall(DMPlexGetTransitiveClosure(dm, c, PETSC_TRUE, &ncl, &closure));
    for (PetscInt i = 0; i < ncl && k < NV; ++i) {
      const PetscInt p = closure[2 * i];
      if (p >= mesh.vStart && p < mesh.vEnd) cell.vertex[k++] = p - mesh.vStart;
    }
    PetscCall(DMPlexRestoreTransitiveClosure(dm, c, PETSC_TRUE, &ncl, &closure));
    // Rest edge matrix in the material frame (C x C).
    EMat<C, C> Dm;
    bool projected = false;
    if constexpr (C == 2) {
      if (mesh.spaceDim == 3) {  // cloth, or a UV map: the 3D triangle in its material frame
        const Eigen::Vector3d X0 = verts_[cell.vertex[0]].rest;
        const Eigen::Vector3d e1 = verts_[cell.vertex[1]].rest - X0, e2 = verts_[cell.vertex[2]].rest - X0;
        Eigen::Vector3d n = e1.cross(e2);
        n = n.norm() > 0.0 ? Eigen::Vector3d(n.normalized()) : Eigen::Vector3d::UnitZ();
        const Eigen::Matrix<double, 3, 2> E = clothFrame(n);
        Dm.col(0) = E.transpose() * e1;
        Dm.col(1) = E.transpose() * e2;
        projected = true;
      }
    }
    if (!projected)
      for (int k2 = 0; k2 < C; ++k2)
        Dm.col(k2) = (verts_[cell.vertex[k2 + 1]].rest - verts_[cell.vertex[0]].rest).template head<C>();
    const double det = Dm.determinant();
    signedMeasure[c - mesh.cStart] = det / (C == 3 ? 6.0 : 2.0);
    cell.measure = std::abs(signedMeasure[c - mesh.cStart]);
    const EMat<C, C> B = std::abs(det) > 0.0 ? EMat<C, C>(Dm.inverse()) : EMat<C, C>::Zero();
    cell.W.row(0) = -B.colwise().sum();
    cell.W.template bottomRows<C>() = B;
    cell.owned = mesh.cellOwned[c - mesh.cStart];
    cell.region = 0;
    for (size_t r = 0; r < regionLabels.size(); ++r) {
      PetscInt val;
      PetscCall(DMLabelGetValue(regionLabels[r].first, c, &val));
      if (val == regionLabels[r].second) cell.region = static_cast<int>(r + 1);
    }
  }
  PetscCall(VecRestoreArrayRead(coordsLocal, &coords));

  // Degenerate or inverted rest cells: one clear error naming the (natural, 0-based gmsh-order) cell.
  {
    double scale = mesh.diagonal;
    const double tiny = 1e-14 * std::pow(scale, C);
    long pos = 0, neg = 0;
    for (double s : signedMeasure) (s > 0 ? pos : neg)++;
    long tot[2] = {pos, neg}, gtot[2];
    PetscCallMPI(MPI_Allreduce(tot, gtot, 2, MPI_LONG, MPI_SUM, comm));
    const double majority = gtot[0] >= gtot[1] ? 1.0 : -1.0;
    std::string msg;
    for (PetscInt c = 0; c < nc && msg.empty(); ++c) {
      const double s = signedMeasure[c];
      if (std::abs(s) <= tiny) {
        std::ostringstream o;
        o << "mesh '" << mesh.filename << "': cell " << mesh.naturalCell[c] << " (0-based, gmsh element order) is "
          << "degenerate: rest " << (C == 3 ? "volume " : "area ") << s << "; fix or remove it";
        msg = o.str();
      } else if (s * majority < 0.0) {
        std::ostringstream o;
        o << "mesh '" << mesh.filename << "': cell " << mesh.naturalCell[c] << " (0-based, gmsh element order) is "
          << "inverted: signed rest " << (C == 3 ? "volume " : "area ") << s * majority
          << " (its orientation disagrees with the mesh); reorder its nodes";
        msg = o.str();
      }
    }
    PetscCall(fem::collectiveCheck(comm, !msg.empty(), msg));
  }
  double localMeasure = 0.0;
  for (const auto &cell : cells_)
    if (cell.owned) localMeasure += cell.measure;
  PetscCallMPI(MPI_Allreduce(&localMeasure, &restMeasure_, 1, MPI_DOUBLE, MPI_SUM, comm));

  // --- anisotropy data: uniform from options, per cell from files ---------------------------------------------------
  bool perCell = !regionLabels.empty();
  std::vector<double> fibers, fibers2;
  std::string fiberFile, fiber2File;
  PetscBool hasFiberFile = PETSC_FALSE, hasFiber2File = PETSC_FALSE;
  bool anyFibers = false;
  for (const auto &m : materials_) {
    bool uses = false;
    PetscCall(materialUsesFibers(m.kind, &uses));
    anyFibers = anyFibers || uses;
  }
  if (anyFibers) {
    PetscCall(optionString(nullptr, "-fiber_file", &fiberFile, &hasFiberFile));
    if (C == 2 && R == 3) PetscCall(optionString(nullptr, "-fiber2_file", &fiber2File, &hasFiber2File));
  }
  if (hasFiberFile) PetscCall(readCellVectorFile(comm, fiberFile, "-fiber_file", mesh.numCellsGlobal, C, &fibers));
  if (hasFiber2File)
    PetscCall(readCellVectorFile(comm, fiber2File, "-fiber2_file", mesh.numCellsGlobal, C, &fibers2));
  // Active materials carry per-cell data (targets, curvature ratios).
  perCell = perCell || hasFiberFile || hasFiber2File || usesEnergy(energies::EnergyKind::ShapeTarget) ||
            usesEnergy(energies::EnergyKind::Caricature);
  auto toData = [&](const UniformCellData &u) { return toCellData<C>(u); };
  if (!perCell) {
    cellData_.assign(1, toData(baseCell));
  } else {
    cellData_.resize(nc);
    for (PetscInt c = 0; c < nc; ++c) {
      energies::CellData<C> d = toData(regionCells[cells_[c].region]);
      const PetscInt nat = mesh.naturalCell[c];
      if (hasFiberFile) d.a = Eigen::Map<const EVec<C>>(&fibers[static_cast<size_t>(nat) * C]);
      if (hasFiber2File) d.b = Eigen::Map<const EVec<C>>(&fibers2[static_cast<size_t>(nat) * C]);
      cellData_[c] = d;
    }
  }
  PetscCall(setupActiveMaterials(mesh));
  restFibers_.resize(nc);
  for (PetscInt c = 0; c < nc; ++c) {
    const auto &a = dataOf(c).a;
    restFibers_[c] = {a[0], a[1], C == 3 ? a[C - 1] : 0.0};
  }

  // --- lumped mass ---------------------------------------------------------------------------------------------------
  mass_.assign(nv, 0.0);
  for (const auto &cell : cells_)
    if (cell.owned)
      for (int v = 0; v < NV; ++v) mass_[cell.vertex[v]] += dyn_.density * cell.measure / NV;
  {
    // Sum the contributions of all ranks on shared vertices.
    std::vector<double> leaf(pEnd - pStart, 0.0), root(pEnd - pStart, 0.0);
    for (PetscInt v = 0; v < nv; ++v) leaf[mesh.vStart + v - pStart] = mass_[v];
    root = leaf;
    PetscCall(PetscSFReduceBegin(pointSF, MPI_DOUBLE, leaf.data(), root.data(), MPI_SUM));
    PetscCall(PetscSFReduceEnd(pointSF, MPI_DOUBLE, leaf.data(), root.data(), MPI_SUM));
    PetscCall(PetscSFBcastBegin(pointSF, MPI_DOUBLE, root.data(), leaf.data(), MPI_REPLACE));
    PetscCall(PetscSFBcastEnd(pointSF, MPI_DOUBLE, root.data(), leaf.data(), MPI_REPLACE));
    for (PetscInt v = 0; v < nv; ++v) mass_[v] = !sharedCopy[mesh.vStart + v - pStart] ? root[mesh.vStart + v - pStart] : leaf[mesh.vStart + v - pStart];
  }
  PetscInt localSize;
  PetscCall(PetscSectionGetStorageSize(localSection, &localSize));
  xTilde_.assign(localSize, 0.0);
  PetscCall(setupSurfaceTerms(mesh, dt));
  PetscFunctionReturn(0);
}


template <int R, int C>
bool DiscretizationT<R, C>::usesEnergy(energies::EnergyKind kind) const {
  for (const auto &m : materials_)
    if (m.kind == kind) return true;
  return false;
}

// Shape targets that vary over the cells or in time (-activation, -target_file), and the caricature's per-cell
// curvature ratio and normal computed from the rest surface (paper Sec. 6).
template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::setupActiveMaterials(Mesh &mesh) {
  MPI_Comm comm;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)mesh.dm, &comm));
  if (usesEnergy(energies::EnergyKind::ShapeTarget)) {
    PetscBool uniform = PETSC_FALSE;
    PetscCall(PetscOptionsHasName(nullptr, nullptr, "-target", &uniform));
    PetscCall(targets_.read(mesh, C, uniform));
    if (targets_.source() != TargetField::Source::Material) updateTargets();
  }
  if (usesEnergy(energies::EnergyKind::Caricature)) {
    if constexpr (R == 3 && C == 3) {
      for (const char *opt : {"-curvature", "-fiber", "-fiber_file"}) {
        PetscBool given = PETSC_FALSE;
        PetscCall(PetscOptionsHasName(nullptr, nullptr, opt, &given));
        if (given)
          SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
                  "option %s does not apply to energy 'caricature' in the solver: each element's curvature ratio c and "
                  "normal n come from the mesh surface (paper Sec. 6); %s is for aries-matpoint",
                  opt, std::string(opt) == "-fiber_file" ? "a uniform -fiber" : opt);
      }
      CaricatureField f;
      PetscCall(computeCaricatureField(mesh, &f));
      for (size_t c = 0; c < cells_.size(); ++c) {
        if (materials_[cells_[c].region].kind != energies::EnergyKind::Caricature) continue;
        cellData_[c].a = f.normal[c];
        cellData_[c].curvature = f.ratio[c];
      }
      PetscCall(PetscPrintf(comm,
                            "aries: caricature field: %d surface vertices, mean curvature %.6g, curvature ratio c in "
                            "[%.4g, %.4g]%s\n",
                            (int)f.surfaceVertices, f.meanCurvature, f.minRatio, f.maxRatio,
                            f.degenerateNormals ? " (some cells without a normal: c = 0)" : ""));
    } else {
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "energy 'caricature' needs a tetrahedral mesh");
    }
  }
  PetscFunctionReturn(0);
}

template <int R, int C>
void DiscretizationT<R, C>::updateTargets() {
  for (size_t c = 0; c < cells_.size(); ++c) {
    if (materials_[cells_[c].region].kind != energies::EnergyKind::ShapeTarget) continue;
    Eigen::Vector3d a = Eigen::Vector3d::Zero();
    a.head<C>() = cellData_[c].a;
    cellData_[c].target = targets_.at(c, time_, load_, a).template topLeftCorner<C, C>();
  }
}

// Cloth bending hinges (-bending, surfaces in 3D) and contact with analytic obstacles (-obstacle_plane,
// -obstacle_sphere; 3D meshes). Options are read only where they apply.
template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::setupSurfaceTerms(Mesh &mesh, double dt) {
  MPI_Comm comm;
  PetscBool set = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)mesh.dm, &comm));
  if constexpr (R == 2 && C == 2) {
    keepOrientation_ = mesh.uvMap ? PETSC_TRUE : PETSC_FALSE;
    PetscCall(optionBool(nullptr, "-keep_orientation", &keepOrientation_, nullptr));
  }
  if constexpr (R == 3 && C == 2) {
    PetscCall(optionReal(nullptr, "-bending", &bending_, &set));
    if (!(bending_ >= 0.0))
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -bending must be >= 0 (got %g)", bending_);
    if (bending_ > 0.0) {
      DM dm = mesh.dm;
      PetscInt eStart, eEnd, nleaves;
      const PetscInt *ilocal;
      PetscSF sf;
      PetscCall(DMPlexGetDepthStratum(dm, 1, &eStart, &eEnd));
      PetscCall(DMGetPointSF(dm, &sf));
      PetscCall(PetscSFGetGraph(sf, nullptr, &nleaves, &ilocal, nullptr));
      std::vector<char> leaf(eEnd - eStart, 0);
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
        h.vertex[0] = cone[0] - mesh.vStart;
        h.vertex[1] = cone[1] - mesh.vStart;
        for (int k = 0; k < 2; ++k) {
          const Cell &cell = cells_[supp[k] - mesh.cStart];
          for (int v = 0; v < NV; ++v)
            if (cell.vertex[v] != h.vertex[0] && cell.vertex[v] != h.vertex[1]) h.vertex[2 + k] = cell.vertex[v];
        }
        h.rest = kernels::bendingHinge(verts_[h.vertex[0]].rest, verts_[h.vertex[1]].rest, verts_[h.vertex[2]].rest,
                                       verts_[h.vertex[3]].rest);
        hinges_.push_back(h);
      }
      PetscCall(DMPlexSetAdjacencyUser(dm, hingeAdjacency, nullptr));
    }
  }
  if constexpr (R == 3) {
    std::vector<PetscReal> planes, spheres;
    PetscBool hasP = PETSC_FALSE, hasS = PETSC_FALSE;
    PetscCall(optionRealList(nullptr, "-obstacle_plane", &planes, &hasP));
    PetscCall(optionRealList(nullptr, "-obstacle_sphere", &spheres, &hasS));
    if (hasP && (planes.empty() || planes.size() % 6))
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
              "option -obstacle_plane takes px,py,pz,nx,ny,nz (a point and the normal towards the free side; 6 "
              "numbers per plane), got %d numbers", (int)planes.size());
    if (hasS && (spheres.empty() || spheres.size() % 4))
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
              "option -obstacle_sphere takes cx,cy,cz,r (4 numbers per sphere), got %d numbers", (int)spheres.size());
    for (size_t k = 0; k < planes.size(); k += 6) {
      kernels::Obstacle o;
      o.kind = kernels::Obstacle::Kind::Plane;
      o.point = Eigen::Vector3d(planes[k], planes[k + 1], planes[k + 2]);
      o.normal = Eigen::Vector3d(planes[k + 3], planes[k + 4], planes[k + 5]);
      if (!(o.normal.norm() > 0.0))
        SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -obstacle_plane: plane %d has a zero normal", (int)(k / 6) + 1);
      o.normal.normalize();
      obstacles_.push_back(o);
    }
    for (size_t k = 0; k < spheres.size(); k += 4) {
      kernels::Obstacle o;
      o.kind = kernels::Obstacle::Kind::Sphere;
      o.point = Eigen::Vector3d(spheres[k], spheres[k + 1], spheres[k + 2]);
      o.radius = spheres[k + 3];
      if (!(o.radius > 0.0))
        SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -obstacle_sphere: sphere %d needs a radius > 0", (int)(k / 4) + 1);
      obstacles_.push_back(o);
    }
    if (!obstacles_.empty()) {
      contactDhat_ = 1e-2 * mesh.diagonal;
      PetscCall(optionReal(nullptr, "-contact_dhat", &contactDhat_, &set));
      if (!(contactDhat_ > 0.0))
        SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -contact_dhat must be > 0 (got %g)", contactDhat_);
      // Default stiffness: the body's own stiffness at a vertex, so contact neither lets vertices sink deep into the
      // barrier's log singularity (slow Newton at impacts) nor dominates the system: with inertia the mean vertex
      // mass / dt^2; quasistatic, modulus * h^(dim - 2) with h = (measure / vertices)^(1/dim) the mean vertex spacing.
      const double perVertex = restMeasure_ / static_cast<double>(mesh.numVerticesGlobal);
      if (dt > 0.0) {
        contactKappa_ = dyn_.density * perVertex / (dt * dt);
      } else {
        const int dim = C;  // 2: surfaces (cloth), 3: solids
        contactKappa_ = characteristicModulus() * std::pow(perVertex, 1.0 - 2.0 / dim);
      }
      PetscCall(optionReal(nullptr, "-contact_stiffness", &contactKappa_, &set));
      if (!(contactKappa_ > 0.0))
        SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -contact_stiffness must be > 0 (got %g)", contactKappa_);
      // The rest shape must be outside every obstacle.
      std::string msg;
      for (size_t v = 0; v < verts_.size() && msg.empty(); ++v)
        for (size_t o = 0; o < obstacles_.size() && msg.empty(); ++o) {
          const double d = kernels::obstacleDistance(obstacles_[o], verts_[v].rest, nullptr);
          if (!(d > 0.0)) {
            std::ostringstream m;
            m << "vertex " << mesh.naturalVertex[v] << " of '" << mesh.filename << "' is inside obstacle " << o + 1
              << " at rest (distance " << d << "); move the obstacle (-obstacle_plane / -obstacle_sphere)";
            msg = m.str();
          }
        }
      PetscCall(fem::collectiveCheck(comm, !msg.empty(), msg));
    }
  }
  PetscFunctionReturn(0);
}

template <int R, int C>
double DiscretizationT<R, C>::surfaceTermsEnergy(const PetscScalar *x, double *magnitude) const {
  double e = 0.0;
  if constexpr (R == 3) {
    for (const Hinge &h : hinges_) {
      Eigen::Vector3d xs[4];
      for (int i = 0; i < 4; ++i) xs[i] = Eigen::Map<const Eigen::Vector3d>(x + verts_[h.vertex[i]].loc);
      e += kernels::quadraticBending(h.rest, xs, bending_, kernels::Order::Value).value;
    }
    if (!obstacles_.empty())
      for (const auto &vi : verts_) {
        if (!vi.owned || vi.bcSet >= 0) continue;
        const Eigen::Vector3d xv = Eigen::Map<const Eigen::Vector3d>(x + vi.loc);
        for (const auto &o : obstacles_)
          e += kernels::obstacleBarrier(o, xv, contactDhat_, contactKappa_, kernels::Order::Value).value;
      }
  }
  if (magnitude) *magnitude += e;  // both terms are >= 0
  return e;
}

template <int R, int C>
void DiscretizationT<R, C>::addSurfaceTermsGradient(const PetscScalar *x, PetscScalar *g) const {
  if constexpr (R == 3) {
    for (const Hinge &h : hinges_) {
      Eigen::Vector3d xs[4];
      for (int i = 0; i < 4; ++i) xs[i] = Eigen::Map<const Eigen::Vector3d>(x + verts_[h.vertex[i]].loc);
      const auto d = kernels::quadraticBending(h.rest, xs, bending_, kernels::Order::Gradient);
      for (int i = 0; i < 4; ++i)
        for (int k = 0; k < 3; ++k) g[verts_[h.vertex[i]].loc + k] += d.grad[3 * i + k];
    }
    if (!obstacles_.empty())
      for (const auto &vi : verts_) {
        if (!vi.owned || vi.bcSet >= 0) continue;
        const Eigen::Vector3d xv = Eigen::Map<const Eigen::Vector3d>(x + vi.loc);
        for (const auto &o : obstacles_) {
          const auto d = kernels::obstacleBarrier(o, xv, contactDhat_, contactKappa_, kernels::Order::Gradient);
          for (int k = 0; k < 3; ++k) g[vi.loc + k] += d.grad[k];
        }
      }
  }
}

template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::addSurfaceTermsHessian(const PetscScalar *x, Mat J) const {
  PetscFunctionBeginUser;
  if constexpr (R == 3) {
    for (const Hinge &h : hinges_) {
      Eigen::Vector3d xs[4];
      for (int i = 0; i < 4; ++i) xs[i] = Eigen::Map<const Eigen::Vector3d>(x + verts_[h.vertex[i]].loc);
      const auto d = kernels::quadraticBending(h.rest, xs, bending_, kernels::Order::Hessian);
      const Eigen::Matrix<double, 12, 12, Eigen::RowMajor> K = d.hess;
      if (blockedAssembly_) {  // 3x3 blocks, as the cells: the off-rank ones go through the block stash
        PetscInt blockRows[4];
        for (int i = 0; i < 4; ++i) {
          const auto &vi = verts_[h.vertex[i]];
          blockRows[i] = vi.bcSet >= 0 ? -1 : vi.global / 3;
        }
        PetscCall(MatSetValuesBlocked(J, 4, blockRows, 4, blockRows, K.data(), ADD_VALUES));
        continue;
      }
      PetscInt rows[12];
      for (int i = 0; i < 4; ++i) {
        const auto &vi = verts_[h.vertex[i]];
        for (int k = 0; k < 3; ++k) rows[3 * i + k] = vi.bcSet >= 0 ? -1 : vi.global + k;
      }
      PetscCall(MatSetValues(J, 12, rows, 12, rows, K.data(), ADD_VALUES));
    }
    if (!obstacles_.empty())
      for (const auto &vi : verts_) {
        if (!vi.owned || vi.bcSet >= 0) continue;
        const Eigen::Vector3d xv = Eigen::Map<const Eigen::Vector3d>(x + vi.loc);
        Eigen::Matrix<double, 3, 3, Eigen::RowMajor> H = Eigen::Matrix3d::Zero();
        for (const auto &o : obstacles_)
          H += kernels::obstacleBarrier(o, xv, contactDhat_, contactKappa_, kernels::Order::Hessian).hess;
        if (H.isZero(0.0)) continue;
        const PetscInt rows[3] = {vi.global, vi.global + 1, vi.global + 2};
        PetscCall(MatSetValues(J, 3, rows, 3, rows, H.data(), ADD_VALUES));
      }
  }
  PetscFunctionReturn(0);
}

template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::fillBoundary(Vec xLocal) const {
  PetscScalar *x;
  PetscFunctionBeginUser;
  PetscCall(VecGetArray(xLocal, &x));
  for (const auto &vi : verts_)
    if (vi.bcSet >= 0) {
      const Eigen::Vector3d t = bc_.sets[vi.bcSet].target(vi.rest, load_);
      for (int i = 0; i < R; ++i) x[vi.loc + i] = t[i];
    }
  PetscCall(VecRestoreArray(xLocal, &x));
  PetscFunctionReturn(0);
}

template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::restPositions(Vec xGlobal) const {
  PetscScalar *x;
  PetscInt lo;
  PetscFunctionBeginUser;
  PetscCall(VecGetOwnershipRange(xGlobal, &lo, nullptr));
  PetscCall(VecGetArray(xGlobal, &x));
  for (const auto &vi : verts_)
    if (vi.owned && vi.bcSet < 0)
      for (int i = 0; i < R; ++i) x[vi.global - lo + i] = vi.rest[i];
  PetscCall(VecRestoreArray(xGlobal, &x));
  PetscFunctionReturn(0);
}

template <int R, int C>
void DiscretizationT<R, C>::forEachOwnedFreeVertex(
    const std::function<void(PetscInt, PetscInt, PetscInt, const Eigen::Vector3d &)> &fn) const {
  for (size_t v = 0; v < verts_.size(); ++v) {
    const auto &vi = verts_[v];
    if (vi.owned && vi.bcSet < 0) fn(static_cast<PetscInt>(v), mesh_->naturalVertex[v], vi.global, vi.rest);
  }
}

template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::setPrediction(Vec xTildeGlobal) {
  Vec loc;
  const PetscScalar *x;
  PetscFunctionBeginUser;
  PetscCall(DMGetLocalVector(mesh_->dm, &loc));
  PetscCall(DMGlobalToLocal(mesh_->dm, xTildeGlobal, INSERT_VALUES, loc));
  PetscCall(VecGetArrayRead(loc, &x));
  std::copy(x, x + xTilde_.size(), xTilde_.begin());
  PetscCall(VecRestoreArrayRead(loc, &x));
  PetscCall(DMRestoreLocalVector(mesh_->dm, &loc));
  PetscFunctionReturn(0);
}

template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::lumpedMass(Vec massGlobal) const {
  PetscScalar *m;
  PetscInt lo;
  PetscFunctionBeginUser;
  PetscCall(VecGetOwnershipRange(massGlobal, &lo, nullptr));
  PetscCall(VecGetArray(massGlobal, &m));
  for (size_t v = 0; v < verts_.size(); ++v) {
    const auto &vi = verts_[v];
    if (vi.owned && vi.bcSet < 0)
      for (int i = 0; i < R; ++i) m[vi.global - lo + i] = mass_[v];
  }
  PetscCall(VecRestoreArray(massGlobal, &m));
  PetscFunctionReturn(0);
}

// Inertia and gravity on owned free vertices: sum_v m_v [ |x_v - x~_v|^2 / (2 dt^2) - g . x_v ].
template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::vertexTermsObjective(const PetscScalar *x, double *E, double *magnitude) const {
  PetscFunctionBeginUser;
  const bool inertia = dyn_.dt > 0.0, grav = dyn_.gravity.squaredNorm() > 0.0;
  double e = 0.0, mag = 0.0;
  if (inertia || grav)
    for (size_t v = 0; v < verts_.size(); ++v) {
      const auto &vi = verts_[v];
      if (!vi.owned || vi.bcSet >= 0) continue;
      for (int i = 0; i < R; ++i) {
        const double xi = x[vi.loc + i];
        if (inertia) {
          const double d = xi - xTilde_[vi.loc + i];
          const double ei = 0.5 * mass_[v] * d * d / (dyn_.dt * dyn_.dt);
          e += ei;
          mag += ei;
        }
        if (grav) {
          const double ei = mass_[v] * dyn_.gravity[i] * xi;
          e -= ei;
          mag += std::abs(ei);
        }
      }
    }
  *E = e;
  if (magnitude) *magnitude += mag;
  PetscFunctionReturn(0);
}

template <int R, int C>
double DiscretizationT<R, C>::cellEnergySum(const PetscScalar *x, double *magnitude) const {
  double e = 0.0, mag = 0.0;
  for (size_t c = 0; c < cells_.size(); ++c) {
    const Cell &cell = cells_[c];
    if (!cell.owned) continue;
    const double ec = cell.measure * energies::evaluateEnergy<R, C>(materialOf(c), dataOf(c),
                                                                    deformationGradient(cell, x), kernels::Order::Value)
                                         .value;
    e += ec;
    mag += std::abs(ec);
  }
  if (magnitude) *magnitude += mag;
  return e;
}

template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::elasticEnergy(Vec xLocal, PetscReal *value) const {
  const PetscScalar *x;
  MPI_Comm comm;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)mesh_->dm, &comm));
  PetscCall(VecGetArrayRead(xLocal, &x));
  const double e = cellEnergySum(x);
  PetscCall(VecRestoreArrayRead(xLocal, &x));
  PetscCallMPI(MPI_Allreduce(&e, value, 1, MPI_DOUBLE, MPI_SUM, comm));
  PetscFunctionReturn(0);
}

template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::objective(Vec xLocal, PetscReal *value, PetscReal *magnitude) const {
  const PetscScalar *x;
  MPI_Comm comm;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)mesh_->dm, &comm));
  PetscCall(VecGetArrayRead(xLocal, &x));
  double sums[2] = {0.0, 0.0}, ev = 0.0;  // energy, magnitude
  PetscCall(vertexTermsObjective(x, &ev, &sums[1]));
  sums[0] = cellEnergySum(x, &sums[1]) + surfaceTermsEnergy(x, &sums[1]) + ev;
  PetscCall(VecRestoreArrayRead(xLocal, &x));
  if (std::isnan(sums[0])) sums[0] = PETSC_INFINITY;  // an undefined state is never accepted by the line search
  double tot[2];
  PetscCallMPI(MPI_Allreduce(sums, tot, magnitude ? 2 : 1, MPI_DOUBLE, MPI_SUM, comm));
  *value = tot[0];
  if (magnitude) *magnitude = tot[1];
  PetscFunctionReturn(0);
}

template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::gradient(Vec xLocal, Vec gLocal) const {
  const PetscScalar *x;
  PetscScalar *g;
  PetscFunctionBeginUser;
  PetscCall(VecSet(gLocal, 0.0));
  PetscCall(VecGetArrayRead(xLocal, &x));
  PetscCall(VecGetArray(gLocal, &g));
  for (size_t c = 0; c < cells_.size(); ++c) {
    const Cell &cell = cells_[c];
    if (!cell.owned) continue;
    const auto d = energies::evaluateEnergy<R, C>(materialOf(c), dataOf(c), deformationGradient(cell, x),
                                                  kernels::Order::Gradient);
    const EMat<R, C> P = cell.measure * kernels::unflatten<R, C>(d.grad);
    for (int v = 0; v < NV; ++v) {
      const EVec<R> gv = P * cell.W.row(v).transpose();
      PetscScalar *gp = g + verts_[cell.vertex[v]].loc;
      for (int i = 0; i < R; ++i) gp[i] += gv[i];
    }
  }
  addSurfaceTermsGradient(x, g);
  const bool inertia = dyn_.dt > 0.0, grav = dyn_.gravity.squaredNorm() > 0.0;
  if (inertia || grav)
    for (size_t v = 0; v < verts_.size(); ++v) {
      const auto &vi = verts_[v];
      if (!vi.owned || vi.bcSet >= 0) continue;
      for (int i = 0; i < R; ++i) {
        if (inertia) g[vi.loc + i] += mass_[v] * (x[vi.loc + i] - xTilde_[vi.loc + i]) / (dyn_.dt * dyn_.dt);
        if (grav) g[vi.loc + i] -= mass_[v] * dyn_.gravity[i];
      }
    }
  PetscCall(VecRestoreArray(gLocal, &g));
  PetscCall(VecRestoreArrayRead(xLocal, &x));
  PetscFunctionReturn(0);
}

template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::hessian(Vec xLocal, Mat J) {
  const PetscScalar *x;
  PetscFunctionBeginUser;
  PetscInt bs;
  PetscCall(MatGetBlockSize(J, &bs));
  blockedAssembly_ = bs == R;
  if (!stashSized_) {
    // Entries for rows another rank owns go through PETSc's stash, which otherwise grows by reallocation during the
    // first assembly: size it for every off-rank row block the cells and hinges add (an upper bound: all columns).
    PetscInt blocks = 0;
    auto offRank = [&](PetscInt v) { return !verts_[v].owned && verts_[v].bcSet < 0; };
    for (const Cell &cell : cells_)
      if (cell.owned)
        for (int v = 0; v < NV; ++v) blocks += offRank(cell.vertex[v]) ? NV : 0;
    for (const Hinge &h : hinges_)
      for (PetscInt v : h.vertex) blocks += offRank(v) ? 4 : 0;
    const PetscInt values = blocks * R * R;
    PetscCall(MatStashSetInitialSize(J, blockedAssembly_ ? 0 : values, blockedAssembly_ ? values : 0));
    stashSized_ = true;
  }
  PetscCall(MatZeroEntries(J));
  PetscCall(VecGetArrayRead(xLocal, &x));
  Eigen::Matrix<double, NDOF, NDOF, Eigen::RowMajor> K;
  for (size_t c = 0; c < cells_.size(); ++c) {
    const Cell &cell = cells_[c];
    if (!cell.owned) continue;
    const auto d = energies::evaluateFilteredEnergy<R, C>(materialOf(c), dataOf(c), deformationGradient(cell, x),
                                                          hessianFilter_);
    const EMat<NF, NF> H = cell.measure * d.hess;
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
    if (blockedAssembly_) {
      PetscInt rows[NV];
      for (int v = 0; v < NV; ++v) {
        const auto &vi = verts_[cell.vertex[v]];
        rows[v] = vi.bcSet >= 0 ? -1 : vi.global / R;
      }
      PetscCall(MatSetValuesBlocked(J, NV, rows, NV, rows, K.data(), ADD_VALUES));
    } else {
      PetscInt rows[NDOF];
      for (int v = 0; v < NV; ++v) {
        const auto &vi = verts_[cell.vertex[v]];
        for (int i = 0; i < R; ++i) rows[v * R + i] = vi.bcSet >= 0 ? -1 : vi.global + i;
      }
      PetscCall(MatSetValues(J, NDOF, rows, NDOF, rows, K.data(), ADD_VALUES));
    }
  }
  PetscCall(addSurfaceTermsHessian(x, J));
  if (dyn_.dt > 0.0)
    for (size_t v = 0; v < verts_.size(); ++v) {
      const auto &vi = verts_[v];
      if (!vi.owned || vi.bcSet >= 0) continue;
      for (int i = 0; i < R; ++i) {
        const PetscInt row = vi.global + i;
        const PetscScalar m = mass_[v] / (dyn_.dt * dyn_.dt);
        PetscCall(MatSetValues(J, 1, &row, 1, &row, &m, ADD_VALUES));
      }
    }
  PetscCall(VecRestoreArrayRead(xLocal, &x));
  PetscCall(MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(0);
}

template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::curvatureGram(Vec xLocal, const std::vector<Vec> &dLocal,
                                                   std::vector<double> *gram) const {
  constexpr int KMAX = 8;
  const int K = static_cast<int>(dLocal.size());
  const PetscScalar *x, *d[KMAX];
  MPI_Comm comm;
  PetscFunctionBeginUser;
  if (K > KMAX) SETERRQ(PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "curvatureGram: at most %d directions", KMAX);
  PetscCall(PetscObjectGetComm((PetscObject)mesh_->dm, &comm));
  PetscCall(VecGetArrayRead(xLocal, &x));
  for (int k = 0; k < K; ++k) PetscCall(VecGetArrayRead(dLocal[k], &d[k]));
  Eigen::Matrix<double, KMAX, KMAX> q = Eigen::Matrix<double, KMAX, KMAX>::Zero();
  // Accumulates sum_k,l a_k^T M a_l for per-term direction pieces a_k (columns of A).
  auto addTerm = [&](const auto &A, const auto &M) {
    const auto MA = (M * A).eval();
    q.topLeftCorner(K, K) += A.transpose() * MA;
  };
  for (size_t c = 0; c < cells_.size(); ++c) {
    const Cell &cell = cells_[c];
    if (!cell.owned) continue;
    const auto e = energies::evaluateEnergy<R, C>(materialOf(c), dataOf(c), deformationGradient(cell, x),
                                                  kernels::Order::Hessian);
    Eigen::Matrix<double, NF, Eigen::Dynamic, 0, NF, KMAX> A(NF, K);
    for (int k = 0; k < K; ++k) A.col(k) = kernels::flatten<R, C>(deformationGradient(cell, d[k]));
    addTerm(A, (cell.measure * e.hess).eval());
  }
  if constexpr (R == 3) {
    for (const Hinge &h : hinges_) {
      Eigen::Vector3d xs[4];
      Eigen::Matrix<double, 12, Eigen::Dynamic, 0, 12, KMAX> A(12, K);
      for (int i = 0; i < 4; ++i) {
        xs[i] = Eigen::Map<const Eigen::Vector3d>(x + verts_[h.vertex[i]].loc);
        for (int k = 0; k < K; ++k) A.col(k).template segment<3>(3 * i) = Eigen::Map<const Eigen::Vector3d>(d[k] + verts_[h.vertex[i]].loc);
      }
      addTerm(A, kernels::quadraticBending(h.rest, xs, bending_, kernels::Order::Hessian).hess);
    }
    if (!obstacles_.empty())
      for (const auto &vi : verts_) {
        if (!vi.owned || vi.bcSet >= 0) continue;
        const Eigen::Vector3d xv = Eigen::Map<const Eigen::Vector3d>(x + vi.loc);
        Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, KMAX> A(3, K);
        for (int k = 0; k < K; ++k) A.col(k) = Eigen::Map<const Eigen::Vector3d>(d[k] + vi.loc);
        for (const auto &o : obstacles_)
          addTerm(A, kernels::obstacleBarrier(o, xv, contactDhat_, contactKappa_, kernels::Order::Hessian).hess);
      }
  }
  if (dyn_.dt > 0.0)
    for (size_t v = 0; v < verts_.size(); ++v) {
      const auto &vi = verts_[v];
      if (!vi.owned || vi.bcSet >= 0) continue;
      const double m = mass_[v] / (dyn_.dt * dyn_.dt);
      for (int i = 0; i < R; ++i)
        for (int k = 0; k < K; ++k)
          for (int l = 0; l < K; ++l) q(k, l) += m * d[k][vi.loc + i] * d[l][vi.loc + i];
    }
  for (int k = 0; k < K; ++k) PetscCall(VecRestoreArrayRead(dLocal[k], &d[k]));
  PetscCall(VecRestoreArrayRead(xLocal, &x));
  std::vector<double> local(K * K);
  for (int k = 0; k < K; ++k)
    for (int l = 0; l < K; ++l) local[k * K + l] = 0.5 * (q(k, l) + q(l, k));
  gram->resize(K * K);
  PetscCallMPI(MPI_Allreduce(local.data(), gram->data(), K * K, MPI_DOUBLE, MPI_SUM, comm));
  PetscFunctionReturn(0);
}

template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::updateBarrierFallback(Vec xLocal, double threshold, PetscInt *count) {
  MPI_Comm comm;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)mesh_->dm, &comm));
  bool anyBarrier = false;
  for (const auto &m : materials_) anyBarrier = anyBarrier || m.singularity.mode == energies::SingularityMode::Barrier;
  PetscInt local = 0;
  if (anyBarrier) {
    if (mollified_.empty()) {
      mollified_ = materials_;
      for (auto &m : mollified_)
        if (m.singularity.mode == energies::SingularityMode::Barrier) m.singularity.mode = energies::SingularityMode::Mollifier;
    }
    std::vector<double> alpha;
    PetscCall(cellAlpha(xLocal, &alpha));
    fallback_.assign(cells_.size(), 0);
    for (size_t c = 0; c < cells_.size(); ++c)
      if (!(alpha[c] > threshold)) {
        fallback_[c] = 1;
        ++local;
      }
  }
  PetscCallMPI(MPI_Allreduce(&local, count, 1, MPIU_INT, MPI_SUM, comm));
  PetscFunctionReturn(0);
}

template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::cellAlpha(Vec xLocal, std::vector<double> *alpha) const {
  const PetscScalar *x;
  PetscFunctionBeginUser;
  alpha->resize(cells_.size());
  PetscCall(VecGetArrayRead(xLocal, &x));
  for (size_t c = 0; c < cells_.size(); ++c) (*alpha)[c] = energies::elementAlpha<R, C>(deformationGradient(cells_[c], x));
  PetscCall(VecRestoreArrayRead(xLocal, &x));
  PetscFunctionReturn(0);
}

template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::cellGuard(Vec xLocal, std::vector<double> *guard) const {
  PetscFunctionBeginUser;
  PetscCall(cellAlpha(xLocal, guard));
  if constexpr (R == 2 && C == 2) {
    if (keepOrientation_) {
      const PetscScalar *x;
      PetscCall(VecGetArrayRead(xLocal, &x));
      for (size_t c = 0; c < cells_.size(); ++c)
        (*guard)[c] = std::min((*guard)[c], deformationGradient(cells_[c], x).determinant());
      PetscCall(VecRestoreArrayRead(xLocal, &x));
    }
  }
  PetscFunctionReturn(0);
}

template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::cellQuantities(Vec xLocal, CellQuantities *q) const {
  const PetscScalar *x;
  PetscFunctionBeginUser;
  q->alpha.resize(cells_.size());
  q->energyDensity.resize(cells_.size());
  PetscCall(VecGetArrayRead(xLocal, &x));
  for (size_t c = 0; c < cells_.size(); ++c) {
    const Cell &cell = cells_[c];
    const EMat<R, C> F = deformationGradient(cell, x);
    q->alpha[c] = energies::elementAlpha<R, C>(F);
    q->energyDensity[c] =
        energies::evaluateEnergy<R, C>(materialOf(c), dataOf(c), F, kernels::Order::Value).value;
  }
  PetscCall(VecRestoreArrayRead(xLocal, &x));
  PetscFunctionReturn(0);
}

template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::cellStressMeasures(Vec xLocal, std::vector<kernels::StressMeasures> *out) const {
  const PetscScalar *x;
  PetscFunctionBeginUser;
  out->resize(cells_.size());
  PetscCall(VecGetArrayRead(xLocal, &x));
  for (size_t c = 0; c < cells_.size(); ++c) {
    const Cell &cell = cells_[c];
    EMat<3, C> Frest = EMat<3, C>::Zero();  // the cell's chart -> rest shape (orthonormal columns)
    for (int v = 0; v < NV; ++v) Frest += verts_[cell.vertex[v]].rest * cell.W.row(v);
    const EMat<R, C> F = deformationGradient(cell, x);
    const auto d = energies::evaluateEnergy<R, C>(materialOf(c), dataOf(c), F, kernels::Order::Gradient);
    (*out)[c] = kernels::stressMeasures<R, C>(F, kernels::unflatten<R, C>(d.grad), Frest);
  }
  PetscCall(VecRestoreArrayRead(xLocal, &x));
  PetscFunctionReturn(0);
}

template <int R, int C>
void DiscretizationT<R, C>::cellRegions(std::vector<double> *regions) const {
  regions->resize(cells_.size());
  for (size_t c = 0; c < cells_.size(); ++c) (*regions)[c] = cells_[c].region;
}

template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::gatherVertexReactions(Vec xLocal, std::vector<double> *values) const {
  PetscFunctionBeginUser;
  Vec g;
  PetscCall(VecDuplicate(xLocal, &g));
  PetscCall(gradient(xLocal, g));  // each rank: its own cells' share at every local vertex (summed by the gather)
  PetscCall(gatherLocalVertexValues(g, [](const VertexInfo &vi) { return vi.bcSet >= 0; }, true, values));
  PetscCall(VecDestroy(&g));
  PetscFunctionReturn(0);
}

template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::gatherVertexMarkers(std::vector<double> *values) const {
  MPI_Comm comm;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)mesh_->dm, &comm));
  std::vector<PetscInt> ids;
  std::vector<double> vals;
  for (size_t v = 0; v < verts_.size(); ++v) {
    if (!verts_[v].owned) continue;
    ids.push_back(mesh_->naturalVertex[v]);
    vals.push_back(verts_[v].bcSet + 1.0);
  }
  PetscCall(gatherNatural(comm, ids, vals, 1, mesh_->numVerticesGlobal, values));
  PetscFunctionReturn(0);
}

template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::reactionForce(Vec xLocal, size_t set, Eigen::Vector3d *force) const {
  MPI_Comm comm;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)mesh_->dm, &comm));
  Vec g;
  PetscCall(VecDuplicate(xLocal, &g));
  PetscCall(gradient(xLocal, g));  // Dirichlet vertices carry only elastic contributions of this rank's cells
  const PetscScalar *ga;
  PetscCall(VecGetArrayRead(g, &ga));
  double f[3] = {0, 0, 0}, tot[3];
  for (const auto &vi : verts_)
    if (vi.bcSet == static_cast<int>(set))
      for (int i = 0; i < R; ++i) f[i] += ga[vi.loc + i];
  PetscCall(VecRestoreArrayRead(g, &ga));
  PetscCall(VecDestroy(&g));
  PetscCallMPI(MPI_Allreduce(f, tot, 3, MPI_DOUBLE, MPI_SUM, comm));
  *force = Eigen::Vector3d(tot[0], tot[1], tot[2]);
  PetscFunctionReturn(0);
}

template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::maxDisplacement(Vec xLocal, PetscReal *value) const {
  const PetscScalar *x;
  MPI_Comm comm;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)mesh_->dm, &comm));
  PetscCall(VecGetArrayRead(xLocal, &x));
  double m = 0.0;
  for (const auto &vi : verts_) {
    double d2 = 0.0;
    for (int i = 0; i < R; ++i) d2 += (x[vi.loc + i] - vi.rest[i]) * (x[vi.loc + i] - vi.rest[i]);
    m = std::max(m, std::sqrt(d2));
  }
  PetscCall(VecRestoreArrayRead(xLocal, &x));
  PetscCallMPI(MPI_Allreduce(&m, value, 1, MPI_DOUBLE, MPI_MAX, comm));
  PetscFunctionReturn(0);
}

template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::gatherLocalVertexValues(Vec local,
                                                              const std::function<bool(const VertexInfo &)> &include,
                                                              bool sumShares, std::vector<double> *values) const {
  const PetscScalar *a;
  MPI_Comm comm;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)mesh_->dm, &comm));
  std::vector<PetscInt> ids;
  std::vector<double> vals;
  PetscCall(VecGetArrayRead(local, &a));
  for (size_t v = 0; v < verts_.size(); ++v) {
    const VertexInfo &vi = verts_[v];
    if (!(sumShares || vi.owned) || !include(vi)) continue;
    ids.push_back(mesh_->naturalVertex[v]);
    for (int i = 0; i < 3; ++i) vals.push_back(i < R ? a[vi.loc + i] : 0.0);
  }
  PetscCall(VecRestoreArrayRead(local, &a));
  PetscCall(gatherNatural(comm, ids, vals, 3, mesh_->numVerticesGlobal, values, sumShares));
  PetscFunctionReturn(0);
}

template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::gatherVertexField(Vec xLocal, std::vector<double> *values) const {
  PetscFunctionBeginUser;
  PetscCall(gatherLocalVertexValues(xLocal, [](const VertexInfo &) { return true; }, false, values));
  PetscFunctionReturn(0);
}

template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::gatherRestPositions(std::vector<double> *values) const {
  MPI_Comm comm;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)mesh_->dm, &comm));
  std::vector<PetscInt> ids;
  std::vector<double> vals;
  for (size_t v = 0; v < verts_.size(); ++v) {
    if (!verts_[v].owned) continue;
    ids.push_back(mesh_->naturalVertex[v]);
    for (int i = 0; i < 3; ++i) vals.push_back(verts_[v].rest[i]);
  }
  PetscCall(gatherNatural(comm, ids, vals, 3, mesh_->numVerticesGlobal, values));
  PetscFunctionReturn(0);
}

template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::gatherCellField(const std::vector<double> &perCell, int components,
                                                      std::vector<double> *values) const {
  MPI_Comm comm;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)mesh_->dm, &comm));
  std::vector<PetscInt> ids;
  std::vector<double> vals;
  for (size_t c = 0; c < cells_.size(); ++c)
    if (cells_[c].owned) {
      ids.push_back(mesh_->naturalCell[c]);
      vals.insert(vals.end(), perCell.begin() + c * components, perCell.begin() + (c + 1) * components);
    }
  PetscCall(gatherNatural(comm, ids, vals, components, mesh_->numCellsGlobal, values));
  PetscFunctionReturn(0);
}

template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::gatherTopology(std::vector<PetscInt> *cellsOut) const {
  MPI_Comm comm;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)mesh_->dm, &comm));
  std::vector<double> conn;
  std::vector<PetscInt> ids;
  for (size_t c = 0; c < cells_.size(); ++c) {
    if (!cells_[c].owned) continue;
    ids.push_back(mesh_->naturalCell[c]);
    for (int v = 0; v < NV; ++v) conn.push_back(static_cast<double>(mesh_->naturalVertex[cells_[c].vertex[v]]));
  }
  std::vector<double> all;
  PetscCall(gatherNatural(comm, ids, conn, NV, mesh_->numCellsGlobal, &all));
  cellsOut->resize(all.size());
  for (size_t i = 0; i < all.size(); ++i) (*cellsOut)[i] = static_cast<PetscInt>(all[i]);
  PetscFunctionReturn(0);
}

template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::cellFibers(std::vector<double> *fibers) const {
  PetscFunctionBeginUser;
  fibers->clear();
  for (const auto &f : restFibers_) fibers->insert(fibers->end(), f.begin(), f.end());
  PetscFunctionReturn(0);
}

PetscErrorCode Discretization::create(Mesh &mesh, double dt, std::unique_ptr<Discretization> *out) {
  PetscFunctionBeginUser;
  switch (mesh.shape) {
    case ElementShape::Tet: {
      auto d = std::make_unique<DiscretizationT<3, 3>>();
      PetscCall(d->setup(mesh, dt));
      *out = std::move(d);
      break;
    }
    case ElementShape::Planar: {
      auto d = std::make_unique<DiscretizationT<2, 2>>();
      PetscCall(d->setup(mesh, dt));
      *out = std::move(d);
      break;
    }
    case ElementShape::Cloth: {
      auto d = std::make_unique<DiscretizationT<3, 2>>();
      PetscCall(d->setup(mesh, dt));
      *out = std::move(d);
      break;
    }
  }
  PetscFunctionReturn(0);
}

}  // namespace aries::fem
