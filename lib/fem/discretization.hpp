// The finite-element discretization (an assembly core with two narrower views: DiagnosticsView for io, Kinematics
// for the solver): per-vertex position unknowns on the DMPlex, Dirichlet vertices eliminated
// through constrained section dofs, per-cell rest data cached once (Dm^-1, rest measure, material, anisotropy
// data), and the assembly of the energy, its gradient and its PSD-projected Hessian (BAIJ) from the closed-form
// element kernels. One implementation per element shape (tet 3x3, planar 2x2, cloth 3x2), behind this interface
// (discretization_impl.hpp lists its files); the total potential is a sum of terms (terms/term.hpp): elastic cells,
// bending hinges, obstacle contact, inertia + gravity, surface loads.
//
// The unknown is the current position x (not the displacement); the global vector holds the free dofs only and a
// local vector additionally holds ghost and Dirichlet values (fillBoundary writes the latter).
#pragma once

#include "energies/material.hpp"
#include "fem/boundary.hpp"
#include "fem/discretization_options.hpp"
#include "fem/material_options.hpp"
#include "mesh/mesh.hpp"
#include "fem/step_state.hpp"
#include "energies/energy.hpp"
#include "kernels/psd_projection.hpp"
#include "kernels/stress_measures.hpp"

#include <petscmat.h>

#include <functional>
#include <memory>

namespace aries::fem {


// Per-cell quantities of a state, on the local cells.
struct CellQuantities {
  std::vector<double> alpha;          // singularity measure
  std::vector<double> energyDensity;  // Psi(F) per unit rest measure
};

// What io reads from a discretization: per-cell quantities of a state, reactions, and the owned vertices' and cells'
// values with their natural (serial gmsh-order) ids for output.
class DiagnosticsView {
 public:
  virtual ~DiagnosticsView() = default;
  // Elastic energy only (for reports).
  virtual PetscErrorCode elasticEnergy(Vec xLocal, PetscReal *value) const = 0;
  // alpha of every local cell at a local state.
  virtual PetscErrorCode cellAlpha(Vec xLocal, std::vector<double> *alpha) const = 0;
  // The smallest alpha over all local cells of all ranks (collective; NaNs skipped, as std::min skips them).
  virtual PetscErrorCode minAlpha(Vec xLocal, PetscReal *min) const = 0;
  virtual PetscErrorCode cellQuantities(Vec xLocal, CellQuantities *q) const = 0;
  // Stress and strain measures of every local cell in the mesh's 3D frame (kernels/stress_measures.hpp).
  virtual PetscErrorCode cellStressMeasures(Vec xLocal, std::vector<kernels::StressMeasures> *out) const = 0;
  // Region of every local cell: 0 = the global material, k = the k-th -regions entry.
  virtual void cellRegions(std::vector<double> *regions) const = 0;
  // Output: values of this rank's owned vertices and cells, in the order of ownedVertexIds / ownedCellIds (their
  // natural, serial gmsh-order ids); io moves them into natural-order blocks (core::NaturalBlocks), no rank gathers.
  virtual void ownedVertexIds(std::vector<PetscInt> *natural, std::vector<PetscInt> *local = nullptr) const = 0;
  virtual void ownedCellIds(std::vector<PetscInt> *natural) const = 0;
  virtual PetscErrorCode ownedVertexValues(Vec local, std::vector<double> *values) const = 0;  // x3 (z = 0 in 2D)
  virtual void ownedRestPositions(std::vector<double> *values) const = 0;                      // x3
  virtual void ownedCellValues(const std::vector<double> &perCell, int components,
                               std::vector<double> *values) const = 0;  // from one value set per local cell
  virtual void ownedTopology(std::vector<PetscInt> *cells) const = 0;   // natural vertex ids per owned cell
  virtual PetscErrorCode cellFibers(std::vector<double> *fibers) const = 0;  // local cells, 3 comps (rest)
  // Per owned vertex (x3): dE/dx in the held components of Dirichlet vertices (the force the support exerts, as
  // -reactions sums it per set, every rank's share added), 0 elsewhere. Collective.
  virtual PetscErrorCode ownedVertexReactions(Vec xLocal, std::vector<double> *values) const = 0;
  // Per owned vertex: k for a vertex of the k-th Dirichlet set (the order of -bc_clamp ids, then -bc_box boxes), 0 if
  // free.
  virtual void ownedVertexMarkers(std::vector<double> *values) const = 0;
  // Reaction force on Dirichlet set `set` (index into boundary().sets): the sum over its vertices of the elastic
  // internal force dE/dx (collective). Pulling a bar by +d gives a reaction along +d.
  virtual PetscErrorCode reactionForce(Vec xLocal, size_t set, Eigen::Vector3d *force) const = 0;
  // Maximum distance of any vertex to its rest position (collective).
  virtual PetscErrorCode maxDisplacement(Vec xLocal, PetscReal *value) const = 0;
};

// What the solver needs beyond the assembled model: vertex positions and the free and supported vertices (initial
// states, the detached start's rigid fit) and the rotational form of a displacement (the rotational update).
// Rigid motion k at rest position X (dofsPerVertex 3: translations e_0..e_2, then rotations e_a x X; planar, 2: the
// two translations, then the rotation about z): the near-nullspace's modes and the supports' free motions.
inline Eigen::Vector3d rigidMotion(int k, int dofsPerVertex, const Eigen::Vector3d &X) {
  if (k < dofsPerVertex) return Eigen::Vector3d::Unit(k);
  return (dofsPerVertex == 3 ? Eigen::Vector3d::Unit(k - 3) : Eigen::Vector3d::UnitZ()).cross(X);
}

class Kinematics {
 public:
  virtual ~Kinematics() = default;
  // Owned vertices with a free component: (local vertex index v - vStart, natural id, the global row of each
  // component (R of them, -1 where prescribed: -bc_clamp_<id>_components), rest position).
  virtual void forEachOwnedFreeVertex(const std::function<void(PetscInt local, PetscInt natural, const PetscInt *rows,
                                                               const Eigen::Vector3d &rest)> &fn) const = 0;
  // Positions of every local vertex at a local state (boundary filled), 3 per vertex in local vertex order (v - vStart;
  // z = 0 for planar unknowns).
  virtual PetscErrorCode vertexPositions(Vec xLocal, std::vector<double> *xyz) const = 0;
  // Local indices (v - vStart) of the owned vertices prescribed in every component.
  virtual void ownedSupportedVertices(std::vector<PetscInt> *local) const = 0;
  // How many independent rigid motions (of 6; planar unknowns: 3) move no prescribed component: the supports' rollers
  // and symmetry planes leave them free (none held: all). Without inertia they have no energy, so a static Hessian is
  // singular along them. Collective.
  virtual PetscErrorCode freeRigidMotions(PetscInt *count) const = 0;
  // The rotational form of a displacement field d at a state x (local vectors, zeros at Dirichlet dofs), in two
  // parts so that several multiples of d share one spin: vertexSpin gives each local vertex's spin w of d (the skew
  // part of grad_x d, averaged over its non-inverted cells; 3 per vertex, collective, zero for planar unknowns);
  // turnBySpin writes out = the share of scale * d that is a rotation by scale * w replaced by the exact rotation by
  // that angle instead of the tangent step (out = scale * d where w = 0).
  virtual PetscErrorCode vertexSpin(Vec xLocal, Vec dLocal, std::vector<double> *spin) const = 0;
  virtual PetscErrorCode turnBySpin(const std::vector<double> &spin, Vec dLocal, double scale, Vec outLocal) const = 0;
};

// The assembly core: the section and boundary values, the step state, the energy, gradient, filtered Hessian and
// curvature of the total potential, and the safeguard's per-cell quantities. Its two views (diagnostics() for io,
// kinematics() for the solver) are the same object seen through narrower interfaces.
class Discretization {
 public:
  virtual ~Discretization() = default;
  // From the options read by readFemOptions (discretization_options.hpp): builds the section, the rest data, the
  // cell data (reading -fiber_file and the per-cell fields' files) and the mass. `dt` is the time step of backward
  // Euler (0 for static runs), the scale of the contact stiffness's default. Collective.
  static PetscErrorCode create(Mesh &mesh, const FemOptions &options, double dt, std::unique_ptr<Discretization> *out);
  // The body without its supports, for the first phase of a static solve from a synthetic start
  // (solver/detached_start.cpp): no Dirichlet vertices, only the elastic terms (no gravity, no contact), everything
  // else copied from this one (nothing is read again). `mesh` must carry its own DM, a DMClone of this one's, since
  // the DOF layout is set on it. Collective.
  virtual PetscErrorCode detachedCopy(Mesh &mesh, std::unique_ptr<Discretization> *out) const = 0;

  DM dm() const { return mesh_->dm; }
  const Mesh &mesh() const { return *mesh_; }
  PetscInt dofsPerVertex() const { return dofs_; }
  const BoundarySpec &boundary() const { return bc_; }
  PetscInt numBoundaryVerticesGlobal() const { return numBcGlobal_; }
  double restMeasureGlobal() const { return restMeasure_; }
  const energies::Material &material(int region = 0) const { return materials_[region]; }
  // Whether some material has fiber terms (energies::energyUsesFibers: alx, fiber, kim_aa, the cloth fibers, ...).
  bool anyFiberTerms() const {
    for (const energies::Material &m : materials_)
      if (energies::energyUsesFibers(m.kind)) return true;
    return false;
  }
  // Whether some material has a volume term lambda/2 (J - J0)^2 with lambda != 0 (nu > 0; energies::energyUsesVolumeTerm).
  bool anyVolumeTerms() const {
    for (const energies::Material &m : materials_)
      if (energies::energyUsesVolumeTerm(m.kind) && m.lambda != 0.0) return true;
    return false;
  }
  // The first material whose mollifier band is on the scale-free coordinate (-mollifier_measure scale_free; the
  // default of degenerate dynamic starts with anisotropic I4/I6 terms), or nullptr.
  const energies::Material *scaleFreeBandMaterial() const {
    for (const energies::Material &m : materials_)
      if (energies::energyContainsStretchInvariant(m.kind) &&
          m.singularity.mode == energies::SingularityMode::Mollifier &&
          m.singularity.mollifier.measure == kernels::MollifierMeasure::ScaleFree)
        return &m;
    return nullptr;
  }
  // Turns the volume terms lambda/2 (J - J0)^2 of every material off (true) or back to their read values (false).
  // Returns whether the energy changed (some material has a volume term with lambda != 0).
  bool suspendVolumeTerms(bool suspend);
  // Whether the materials' terms other than the volume terms fix the rest shape up to a rigid motion, to second order:
  // in every cell they are stationary at the rest deformation gradient (I; the target for shape_target) and their
  // Hessian there has only the three rotations' zero eigenvalues and none below. False for planar and cloth elements.
  // Collective.
  virtual PetscErrorCode stretchTermsFixShape(bool *fixes) const = 0;
  double characteristicModulus() const;  // largest shear-like modulus (for scaling tolerances and reports)
  const DynamicsTerms &dynamics() const { return dyn_; }

  // The step being solved for (fem/step_state.hpp): the load parameter of the prescribed motion and the resulting
  // Dirichlet values, the time (keyframed shape targets, -target_file), and for backward Euler dt and the prediction
  // x~ of the incremental potential 1/(2 dt^2) |x - x~|_M^2 (gravity enters as -M g . x). Static runs have dt = 0.
  virtual PetscErrorCode setStep(const StepState &step) = 0;
  const StepState &step() const { return step_; }
  double load() const { return step_.load; }
  double time() const { return step_.time; }
  // Writes the Dirichlet values of the step's load into a local vector (its other entries are left as they are).
  PetscErrorCode fillBoundary(Vec xLocal) const { return fillBoundary(xLocal, step_.load); }
  // ... or of the prescribed motion at load parameter `load` (the lifted increment's boundary move).
  virtual PetscErrorCode fillBoundary(Vec xLocal, double load) const = 0;

  // Rest positions of the free dofs (global vector).
  virtual PetscErrorCode restPositions(Vec xGlobal) const = 0;
  virtual PetscErrorCode lumpedMass(Vec massGlobal) const = 0;  // per free dof

  // Total potential (elastic + inertia + gravity) and its derivatives at a local state (boundary filled).
  // `magnitude` (optional): the sum of the absolute values of the energy's terms, the scale of its round-off error.
  virtual PetscErrorCode objective(Vec xLocal, PetscReal *value, PetscReal *magnitude = nullptr) const = 0;
  virtual PetscErrorCode gradient(Vec xLocal, Vec gLocal) const = 0;  // gLocal zeroed here; add to global with ADD_VALUES
  virtual PetscErrorCode hessian(Vec xLocal, Mat J) = 0;        // assembled, eigenvalue-filtered per element
  // The same filtered Hessian times a local vector d, every local dof included (free and prescribed): y = H d in the
  // local layout (yLocal zeroed here; add to a global vector with ADD_VALUES, which keeps the free rows). With d zero
  // at the free dofs it is H_fd d_d, the coupling of a prescribed increment into the free equations.
  virtual PetscErrorCode hessianProduct(Vec xLocal, Vec dLocal, Vec yLocal) const = 0;
  // Preallocates J (a matrix of this DM's layout created with DMSetMatrixPreallocateSkip) from the terms themselves:
  // the blocks their element and vertex matrices touch (elastic cells of any element type, bending hinges, pressure
  // faces, contact and inertia), whatever couples what. Collective.
  virtual PetscErrorCode preallocateHessian(Mat J) const = 0;
  // The element Hessians' eigenvalue filter used by hessian() (kernels/psd_projection.hpp); the Newton solver picks it
  // per iteration (-psd_projection).
  void setEigenFilter(kernels::EigenFilter filter) { hessianFilter_.filter = filter; }
  kernels::EigenFilter eigenFilter() const { return hessianFilter_.filter; }
  // Closed-form eigensystems where an energy has one (-psd_eigensystem analytic), else the numeric eigensolve.
  void setAnalyticEigensystem(bool analytic) { hessianFilter_.analytic = analytic; }
  // -psd_scope element: the filter projects each element's whole Hessian (vertex coordinates, summed over its points)
  // instead of each point's F-space Hessian.
  void setWholeElementFilter(bool whole) { wholeElementFilter_ = whole; }
  // Gram matrix G_kl = d_k^T H d_l of K <= 8 directions d_k (local vectors with zeros at the Dirichlet dofs) with the
  // true (unfiltered) Hessian H of the total potential at a local state; row-major K x K, collective. The contact term
  // enters with its PSD Hessian (kernels/obstacle_barrier.hpp). Used by the Newton solver's subspace step and the
  // adaptive filter's trust-region ratio.
  virtual PetscErrorCode curvatureGram(Vec xLocal, const std::vector<Vec> &dLocal, std::vector<double> *gram) const = 0;
  // Barrier mode at singular elements (paper Sec. 7.1): elements whose alpha is below `threshold` in this state are
  // evaluated with the mollifier instead of the aberration barrier (b is undefined at alpha = 0) until a later
  // call finds them above it. Called at the start of each step, so every Newton solve sees one fixed energy.
  // Returns the number of such elements (collective).
  virtual PetscErrorCode updateBarrierFallback(Vec xLocal, double threshold, PetscInt *count) = 0;

  // The quantity the safeguard keeps above -alpha_min: alpha, or min(alpha, det F) for planar elements under
  // -keep_orientation (in 2D alpha = s1 + s2 stays positive when a triangle flips, det F does not). Exact below
  // `exactBelow`; where it is at least that, any value in [exactBelow, it] (ElasticCells::guard): the safeguard
  // compares it with thresholds up to exactBelow only, and near-rest cells then need no root.
  virtual PetscErrorCode cellGuard(Vec xLocal, double exactBelow, std::vector<double> *guard) const = 0;
  // Top of each local cell's singular band for the safeguard: the mollifier's eps for cells evaluated with the
  // mollifier (below it their I4/I6 terms are the constant proxy, Eq. 33: nothing is singular there), 0 otherwise.
  virtual void mollifierBandTop(std::vector<double> *top) const = 0;
  // Cells whose aberration barrier is active at a local state: evaluated in barrier mode (not fallen back to the
  // mollifier) with 0 < alpha < the barrier's eps (collective count).
  virtual PetscErrorCode barrierActiveCells(Vec xLocal, PetscInt *count) const = 0;
  // Cells held at the mollifier's band at a local state: evaluated with the mollifier, with I4/I6 terms, and some
  // point's alpha in [eps, kMollifierBandEdge * 3 eps] (the band of Eq. 33 and just above it, where the raw terms'
  // forces peak; collective count). A failed anisotropic scramble's Newton solve ends with a cell that approaches
  // alpha = 3 eps from above until the line search fails there (bench/results/degenerate_starts_band.md): the failed
  // step's hint names them.
  virtual PetscErrorCode mollifierBandCells(Vec xLocal, PetscInt *count) const = 0;
  static constexpr double kMollifierBandEdge = 2.0;

  // A local Newton solve's focus (solver/local_solve.cpp): the dofs marked nonzero in a local vector (ghosts included:
  // every rank marks the vertices whose cells it owns). While set, the elastic cells sum only their owned cells with a
  // marked vertex (the other terms all their pieces: correct, since only the marked dofs move), so objective()
  // differences between states that differ at marked dofs only, and the gradient's and Hessian's marked rows, are
  // the whole model's; cellGuard() gives those cells' values and +inf elsewhere. nullptr ends the focus.
  virtual PetscErrorCode setFocus(Vec markLocal) = 0;
  // Writes 1 into every dof of every vertex of the focus's cells on this rank (a local vector; others left as they
  // are): summed into a global vector over the ranks, the focus's vertices and their neighbours, whatever the
  // partition.
  virtual PetscErrorCode markFocusVertices(Vec outLocal) const = 0;

  virtual PetscInt verticesPerCell() const = 0;  // nodes per element: 4 (tet), 3 (triangle), 8 (hexahedron), 10 (P2)
  virtual const char *outputTopology() const = 0;  // the element type's XDMF TopologyType
  virtual int shapeCols() const = 0;
  virtual const DiagnosticsView &diagnostics() const = 0;
  virtual const Kinematics &kinematics() const = 0;

 protected:
  Mesh *mesh_ = nullptr;
  PetscInt dofs_ = 3;
  BoundarySpec bc_;
  PetscInt numBcGlobal_ = 0;
  double restMeasure_ = 0.0;
  std::vector<energies::Material> materials_;
  std::vector<double> lambdaRead_;  // the materials' lambda as read, while suspendVolumeTerms(true) holds
  DynamicsTerms dyn_;
  energies::HessianFilter hessianFilter_;
  bool wholeElementFilter_ = false;
  StepState step_;
};

}  // namespace aries::fem
