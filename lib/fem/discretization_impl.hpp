// The discretization for one element type (kernels/elements/: tet 3x3, hexahedron 3x3, planar 2x2, cloth 3x2):
// internal to lib/fem. Its parts live in one file per responsibility:
//   discretization.cpp   setup order, the step state, boundary values, rest positions, mass
//   dof_layout.cpp       Dirichlet marking, the PetscSection, the vertex table, clamp centers
//   rest_geometry.cpp    per-cell rest data (the element type's W_q, w_q, measure), degenerate/inverted cell checks,
//                        lumped mass
//   cell_data.cpp        materials and regions, fibers, the per-cell fields the energies name (cell_fields.hpp)
//   assembly.cpp         objective, gradient, Hessian and curvature as loops over the terms (terms/)
//   diagnostics.cpp      per-cell quantities, stress, reactions, owned values with natural ids for output
#pragma once

#include "fem/discretization.hpp"
#include "fem/element_types.hpp"
#include "fem/material_options.hpp"
#include "fem/cell_fields.hpp"
#include "fem/terms/bending_hinges.hpp"
#include "fem/terms/elastic_cells.hpp"
#include "fem/terms/inertia_gravity.hpp"
#include "fem/terms/obstacle_contact.hpp"
#include "fem/terms/follower_pressure.hpp"
#include "fem/terms/surface_loads.hpp"
#include "fem/vertex_layout.hpp"

#include <memory>
#include <vector>

namespace aries::fem {


// One instance per element type (fem/element_types.hpp), named by the shape of its F (R x C) and its nodes per element
// NV (C + 1: linear simplices; 8: trilinear hexahedra; 10: quadratic tetrahedra).
template <int R, int C, int NV = C + 1>
class DiscretizationT final : public Discretization, public DiagnosticsView, public Kinematics {
 public:
  using Element = kernels::ElementOf<R, C, NV>;  // the element type (kernels/elements/, fem/element_types.hpp)
  using Cells = ElasticCells<R, C, NV>;
  using Cell = typename Cells::Cell;
  static constexpr int NQ = Cells::NQ;

  PetscErrorCode setup(Mesh &mesh, const FemOptions &o, double dt);
  PetscErrorCode detachedCopy(Mesh &mesh, std::unique_ptr<Discretization> *out) const override;

  PetscErrorCode setStep(const StepState &step) override;
  using Discretization::fillBoundary;
  PetscErrorCode fillBoundary(Vec xLocal, double load) const override;
  PetscErrorCode restPositions(Vec xGlobal) const override;
  PetscErrorCode lumpedMass(Vec massGlobal) const override;
  PetscErrorCode objective(Vec xLocal, PetscReal *value, PetscReal *magnitude = nullptr) const override;
  PetscErrorCode gradient(Vec xLocal, Vec gLocal) const override;
  PetscErrorCode hessian(Vec xLocal, Mat J) override;
  PetscErrorCode hessianProduct(Vec xLocal, Vec dLocal, Vec yLocal) const override;
  PetscErrorCode preallocateHessian(Mat J) const override;
  PetscErrorCode curvatureGram(Vec xLocal, const std::vector<Vec> &dLocal, std::vector<double> *gram) const override;
  PetscErrorCode elasticEnergy(Vec xLocal, PetscReal *value) const override;
  PetscErrorCode updateBarrierFallback(Vec xLocal, double threshold, PetscInt *count) override;
  PetscErrorCode cellAlpha(Vec xLocal, std::vector<double> *alpha) const override;
  PetscErrorCode minAlpha(Vec xLocal, PetscReal *min) const override;
  PetscErrorCode cellGuard(Vec xLocal, double exactBelow, std::vector<double> *guard) const override;
  PetscErrorCode cellQuantities(Vec xLocal, CellQuantities *q) const override;
  PetscErrorCode barrierActiveCells(Vec xLocal, PetscInt *count) const override;
  PetscErrorCode mollifierBandCells(Vec xLocal, PetscInt *count) const override;
  void mollifierBandTop(std::vector<double> *top) const override;
  PetscErrorCode setFocus(Vec markLocal) override;
  PetscErrorCode markFocusVertices(Vec outLocal) const override;
  void ownedVertexIds(std::vector<PetscInt> *natural, std::vector<PetscInt> *local = nullptr) const override;
  void ownedCellIds(std::vector<PetscInt> *natural) const override;
  PetscErrorCode ownedVertexValues(Vec local, std::vector<double> *values) const override;
  void ownedRestPositions(std::vector<double> *values) const override;
  void ownedCellValues(const std::vector<double> &perCell, int components, std::vector<double> *values) const override;
  void ownedTopology(std::vector<PetscInt> *cells) const override;
  PetscErrorCode cellFibers(std::vector<double> *fibers) const override;
  int shapeCols() const override { return C; }
  PetscInt verticesPerCell() const override { return NV; }
  const char *outputTopology() const override { return Element::kXdmfTopology; }
  const DiagnosticsView &diagnostics() const override { return *this; }
  const Kinematics &kinematics() const override { return *this; }
  void forEachOwnedFreeVertex(
      const std::function<void(PetscInt, PetscInt, const PetscInt *, const Eigen::Vector3d &)> &fn) const override;
  PetscErrorCode maxDisplacement(Vec xLocal, PetscReal *value) const override;
  PetscErrorCode stretchTermsFixShape(bool *fixes) const override;
  PetscErrorCode vertexSpin(Vec xLocal, Vec dLocal, std::vector<double> *spin) const override;
  PetscErrorCode turnBySpin(const std::vector<double> &spin, Vec dLocal, double scale, Vec outLocal) const override;
  PetscErrorCode vertexPositions(Vec xLocal, std::vector<double> *xyz) const override;
  void ownedSupportedVertices(std::vector<PetscInt> *local) const override;
  PetscErrorCode freeRigidMotions(PetscInt *count) const override;
  PetscErrorCode reactionForce(Vec xLocal, size_t set, Eigen::Vector3d *force) const override;
  PetscErrorCode cellStressMeasures(Vec xLocal, std::vector<kernels::StressMeasures> *out) const override;
  void cellRegions(std::vector<double> *regions) const override;
  PetscErrorCode ownedVertexReactions(Vec xLocal, std::vector<double> *values) const override;
  void ownedVertexMarkers(std::vector<double> *values) const override;

 private:
  // Setup, in this order (discretization.cpp).
  PetscErrorCode refuseOnPointRules(const Mesh &mesh, const FemOptions &o) const;                // discretization
  PetscErrorCode markDirichlet(const Mesh &mesh, const std::vector<Eigen::Vector3d> &rest,
                               std::vector<PetscInt> *bcFlag);                                   // dof_layout.cpp
  PetscErrorCode layoutDofs(const Mesh &mesh, const std::vector<Eigen::Vector3d> &rest,
                            const std::vector<PetscInt> &bcFlag);                                // dof_layout.cpp
  PetscErrorCode setupRestCells(const Mesh &mesh, const std::vector<std::pair<DMLabel, PetscInt>> &regionLabels);
  PetscErrorCode checkRestCells(const Mesh &mesh, const std::vector<double> &signedMeasure) const;  // rest_geometry
  PetscErrorCode setupCellData(Mesh &mesh, const FemOptions &o, const std::vector<UniformCellData> &regionCells,
                               bool regions);                                                    // cell_data.cpp
  PetscErrorCode setupMass(const Mesh &mesh);                                                    // rest_geometry
  PetscErrorCode setupTerms(Mesh &mesh, const FemOptions &o, double dt);                         // discretization
  PetscErrorCode addBendingHinges(Mesh &mesh, double stiffness);                                 // discretization
  PetscErrorCode addInertiaGravity(const Mesh &mesh);                                            // discretization

  // Each local cell's guard value exact below exactBelow (the safeguard's guard, alpha at +inf; diagnostics.cpp).
  void elasticGuards(const PetscScalar *x, double exactBelow, std::vector<double> *guard) const;
  // `comps` values per owned vertex, value(local vertex, out), in the order of ownedVertexIds.
  void ownedVertexRows(int comps, const std::function<void(size_t, double *)> &value, std::vector<double> *values) const;
  MPI_Comm comm() const { return PetscObjectComm((PetscObject)mesh_->dm); }

  VertexTable verts_;
  Cells cells_{verts_, materials_};
  std::vector<std::array<double, 3>> restFibers_;  // per cell, for output (material frame)
  CellFields<C> fields_;                           // the per-cell fields the materials name (cell_fields.hpp)
  std::vector<double> mass_;                       // per local vertex: lumped
  std::vector<double> gravityMass_;                // per local vertex: the consistent load's int rho N_v
  PetscBool keepOrientation_ = PETSC_FALSE;        // -keep_orientation (planar elements)
  std::unique_ptr<BendingHinges> hinges_;          // -bending (cloth)
  std::unique_ptr<ObstacleContact> contact_;       // -obstacle_plane / -obstacle_sphere (3D)
  std::unique_ptr<InertiaGravity<R>> inertia_;     // backward Euler and -gravity
  std::unique_ptr<SurfaceLoads<R>> loads_;         // -load_traction_<set>, -load_force_<set>
  std::unique_ptr<FollowerPressure<PressureFaceOf<Element>>> pressure_;  // -load_pressure_<set> (volume meshes)
  std::vector<const Term *> terms_;                // the active terms, in assembly order
  bool stashSized_ = false;  // the off-rank assembly buffer sized before the first Hessian assembly
};

}  // namespace aries::fem
