// Dirichlet boundary conditions (documented in docs/options.md):
//   -bc_clamp id1,id2,...              gmsh physical groups (ids or names) whose vertices are prescribed
//   -bc_clamp_<id>_translate x,y,z     total translation of the set, ramped linearly with the load parameter
//   -bc_clamp_<id>_rotate degrees      total rotation angle of the set about ...
//   -bc_clamp_<id>_axis x,y,z          ... this axis (default 0,0,1) through ...
//   -bc_clamp_<id>_center x,y,z        ... this point (default: centroid of the set at rest)
//   -bc_clamp_<id>_affine a11,...,a33  a homogeneous deformation x = A X (about the origin), applied first
//   -bc_clamp_<id>_components x,z      only these components are prescribed (symmetry planes, rollers)
//   -bc_box xmin,xmax,ymin,ymax,zmin,zmax[,...]   vertices inside box k (1-based) are prescribed, pinned at rest
//   -bc_box_<k>_translate|rotate|axis|center|components   unless moved like a clamp set (handles)
//   -bc_box_<k>_surface                only the vertices of the mesh's boundary facets inside box k
//   -bc_ramp_steps K                   the load parameter s = min(1, step / K) (default: all steps)
// A vertex in several sets is held in the union of their components, each component by the first set (clamp sets in
// the order listed, then boxes) that prescribes it. Prescribed position at load s:
//   x = c + Rot(axis, s * angle) (X' - c) + s * translate,  X' = X + s (A - I) X.
#pragma once

#include <petscsys.h>

#include <Eigen/Dense>

#include <array>
#include <string>
#include <vector>

namespace aries::fem {

struct ClampSet {
  std::string id;  // as given (number or name)
  Eigen::Vector3d translate = Eigen::Vector3d::Zero();
  double angleDeg = 0.0;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  bool centerGiven = false;
  Eigen::Matrix3d affine = Eigen::Matrix3d::Identity();  // x = A X about the origin, first
  unsigned components = 0b111;                           // bit i: component i is prescribed
  bool componentsGiven = false;                          // -bc_clamp_<id>_components set (z on a 2D mesh: an error)
  bool surfaceOnly = false;                              // a box's boundary vertices only (-bc_box_<k>_surface)

  Eigen::Vector3d target(const Eigen::Vector3d &X, double s) const;
};

struct BoundarySpec {
  std::vector<ClampSet> sets;                // clamped physical groups, then one entry per box (pinned)
  std::vector<std::array<double, 6>> boxes;  // index in `sets`: numGroups + box index
  PetscInt rampSteps = -1;                   // -1: the number of steps
  size_t numGroups() const { return sets.size() - boxes.size(); }
};

PetscErrorCode readBoundaryOptions(BoundarySpec *spec);

}  // namespace aries::fem
