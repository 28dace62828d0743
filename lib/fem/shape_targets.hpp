// Per-element shape targets S_t of the `shape_target` energy (paper Sec. 5.3, Eq. 65), as a field over the cells:
//   -target s11,...          one constant target for every cell (material option, docs/options.md)
//   -activation l1[,l2]      muscle-like activation along each cell's fiber a (-fiber / -fiber_file):
//                            S_t = l1 a a^T + l2 (I - a a^T), reached by the load ramp (-bc_ramp_steps):
//                            S_t(s) = I + s (S_t - I), s = load parameter. l2 = 0 is the additive iso + fiber
//                            muscle form of the paper (lambda_i = 0 for i > 1).
//   -target_file FILE        per-cell keyframes (format in mesh/cell_files.hpp), linear in time, held constant
//                            before the first and after the last keyframe.
#pragma once

#include "mesh/mesh.hpp"

#include <Eigen/Dense>

#include <vector>

#include "fem/cell_fields.hpp"

namespace aries::fem {

class TargetField {
 public:
  enum class Source { Material, Activation, Keyframes };

  // Reads -activation / -target_file (at most one, and not with -target). `dim` = 2 or 3. Collective.
  PetscErrorCode read(const Mesh &mesh, int dim, bool uniformTargetGiven);
  Source source() const { return source_; }
  bool timeDependent() const { return source_ == Source::Keyframes; }
  bool loadDependent() const { return source_ == Source::Activation; }

  // S_t of local cell c (index c - cStart) at time t, load s, with unit fiber a (first `dim` entries used).
  Eigen::Matrix3d at(size_t c, double t, double s, const Eigen::Vector3d &a) const;

 private:
  Source source_ = Source::Material;
  int dim_ = 3, comps_ = 6;
  double along_ = 1.0, across_ = 1.0;
  std::vector<double> times_;
  std::vector<double> local_;  // keyframe k, local cell c: local_[(k * ncells + c) * comps_ ...]
  size_t ncells_ = 0;
  Eigen::Matrix3d keyframe(size_t k, size_t c) const;
};

// The shape_target energy's per-cell field (energies::CellField::ShapeTargets): S_t from -activation (along each
// cell's fiber, ramped with the load) or -target_file (keyframes in time); with neither, the material's -target.
template <int C>
std::unique_ptr<CellFieldSource<C>> makeShapeTargetSource();

}  // namespace aries::fem
