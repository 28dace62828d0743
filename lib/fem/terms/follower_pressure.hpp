// Follower pressure on closed boundary surfaces (-load_pressure_<set> p, the default -load_pressure_<set>_kind
// follower), on every volume element: linear tetrahedra (3-node faces), trilinear hexahedra (bilinear 4-node faces)
// and quadratic tetrahedra (6-node faces, curved once deformed); ramped with the load parameter s. The pressure p acts
// on the deformed surface against its outward normal (the body's), so p > 0 on the outer surface squeezes the body and
// p > 0 on a cavity's wall inflates the cavity. On a closed surface it is conservative: its potential is
// s p (V(x) - V(X)), V the volume the surface encloses with the body's outward orientation, (1/3) int (x - c) . n da
// face by face (kernels::faceVolume, exact quadrature for each face type; a cavity's wall encloses minus the cavity's
// volume), so Newton minimizes one total potential and its Hessian is symmetric. That Hessian is indefinite (trace-free
// per face): each face's block goes through the same eigenvalue filter as the elements (-psd_projection) so CG sees a
// PSD system; the subspace step and the adaptive filter use the true one. An open set has no potential (its load is
// not conservative): a follower pressure on one is an error that names the dead pressure (terms/surface_loads.hpp).
#pragma once

#include "fem/discretization_options.hpp"
#include "mesh/mesh.hpp"
#include "fem/terms/term.hpp"
#include "fem/vertex_layout.hpp"
#include "kernels/enclosed_volume.hpp"

#include <array>
#include <string>
#include <type_traits>
#include <vector>

namespace aries::fem {

template <class Face>
class FollowerPressure final : public Term {
 public:
  static constexpr int kNodes = Face::kNodes;
  explicit FollowerPressure(const VertexTable &verts) : verts_(verts) {}
  // The faces of every follower pressure load owned by this rank, ordered with the body's outward normal. A set not in
  // the mesh, without boundary faces, with a face inside the body, or not closed is a one-line error. Collective.
  PetscErrorCode setup(const Mesh &mesh, const std::vector<SurfaceLoad> &loads);
  bool empty() const { return loads_ == 0; }
  void setLoad(double s) { s_ = s; }
  const char *name() const override { return "follower pressure"; }
  void addEnergy(const PetscScalar *x, double *energy, double *magnitude) const override;
  void addGradient(const PetscScalar *x, PetscScalar *g) const override;
  PetscErrorCode addHessian(const PetscScalar *x, const HessianAssembly &how, Mat J) const override;
  void addCurvature(const PetscScalar *x, const PetscScalar *const d[], int K, GramMatrix *q) const override;
  PetscInt offRankHessianValues() const override;

 private:
  struct PressureFace {
    std::array<PetscInt, kNodes> vertex;  // local vertex indices, Face's node order, outward
    int set;                         // index of its load
  };
  kernels::Mat<kNodes, 3> positions(const PressureFace &f, const PetscScalar *x) const;
  kernels::Mat<kNodes, 3> restPositions(const PressureFace &f) const;
  const VertexTable &verts_;
  std::vector<PressureFace> faces_;
  std::vector<double> pressure_;         // per load: p at load 1
  std::vector<Eigen::Vector3d> center_;  // per load: the set's rest centroid (the pieces' reference point)
  std::vector<double> restVolume_;       // per load: this rank's share of V(X) (the potential's datum)
  size_t loads_ = 0;
  double s_ = 0.0;
};

// The face type of an element type E (kernels/elements/): E::Face for a volume element; a 2D element's faces are edges,
// which carry no pressure (the term is never made for it: Tri3 only names a type).
template <class E>
using PressureFaceOf = std::conditional_t<std::is_void_v<typename E::Face>, kernels::face::Tri3, typename E::Face>;

}  // namespace aries::fem
