#include "fem/boundary.hpp"

#include "core/options.hpp"
#include "fem/fem_options.hpp"

#include <cmath>

namespace aries::fem {

using core::optionName;

Eigen::Vector3d ClampSet::target(const Eigen::Vector3d &X, double s) const {
  Eigen::Vector3d x = X + s * (affine - Eigen::Matrix3d::Identity()) * X;
  if (angleDeg != 0.0) {
    const double angle = s * angleDeg * M_PI / 180.0;
    x = center + Eigen::AngleAxisd(angle, axis) * (x - center);
  }
  return x + s * translate;
}

namespace {

// The motion options of one set: <prefix>translate, rotate, axis, center, affine, components.
PetscErrorCode readMotion(const std::string &prefix, ClampSet *c) {
  std::vector<PetscReal> v;
  std::vector<std::string> comps;
  PetscBool set = PETSC_FALSE;
  PetscFunctionBeginUser;
  const core::ReadContext at{prefix.c_str()};
  PetscCall(core::get(opt::clampComponents, &comps, &set, at));
  if (set) {
    c->componentsGiven = true;
    c->components = 0;
    for (const auto &w : comps) {
      const unsigned bit = w == "x" ? 1u : w == "y" ? 2u : w == "z" ? 4u : 0u;
      if (!bit || (c->components & bit))
        SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s: '%s' is %s (components are x, y, z, each once)",
                optionName(prefix.c_str(), "-components").c_str(), w.c_str(), bit ? "listed twice" : "not a component");
      c->components |= bit;
    }
    if (!c->components)
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s lists no component (x, y, z)",
              optionName(prefix.c_str(), "-components").c_str());
  }
  PetscCall(core::get(opt::clampTranslate, &v, &set, at));
  c->translate = Eigen::Vector3d(v[0], v[1], v[2]);
  PetscCall(core::get(opt::clampAffine, &v, &set, at));
  if (set) {
    const int d = v.size() == 9 ? 3 : 2;
    for (int i = 0; i < d; ++i)
      for (int j = 0; j < d; ++j) c->affine(i, j) = v[d * i + j];
  }
  PetscCall(core::get(opt::clampRotate, &c->angleDeg, &set, at));
  if (set) {
    PetscCall(core::get(opt::clampAxis, &v, &set, at));
    c->axis = Eigen::Vector3d(v[0], v[1], v[2]);
    if (!(c->axis.norm() > 0.0))
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s must not be the zero vector",
              optionName(prefix.c_str(), "-axis").c_str());
    c->axis.normalize();
    PetscCall(core::get(opt::clampCenter, &v, &set, at));
    if (set) {
      c->center = Eigen::Vector3d(v[0], v[1], v[2]);
      c->centerGiven = true;
    }
  }
  PetscFunctionReturn(0);
}

}  // namespace

PetscErrorCode readBoundaryOptions(BoundarySpec *spec) {
  std::vector<std::string> ids;
  PetscBool set = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCall(core::get(opt::clamp, &ids, &set));
  for (const auto &id : ids) {
    for (const auto &other : spec->sets)
      if (other.id == id) SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -bc_clamp lists '%s' twice", id.c_str());
    ClampSet c;
    c.id = id;
    PetscCall(readMotion("bc_clamp_" + id + "_", &c));
    spec->sets.push_back(c);
  }
  std::vector<PetscReal> box;
  PetscCall(core::get(opt::boxes, &box, &set));
  if (set) {
    if (box.empty() || box.size() % 6 != 0)
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
              "option -bc_box takes xmin,xmax,ymin,ymax,zmin,zmax (6 numbers per box), got %d numbers",
              (int)box.size());
    for (size_t b = 0; b < box.size(); b += 6) {
      std::array<double, 6> bb;
      for (int k = 0; k < 6; ++k) bb[k] = box[b + k];
      if (bb[0] > bb[1] || bb[2] > bb[3] || bb[4] > bb[5])
        SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -bc_box: box %d has min > max", (int)(b / 6) + 1);
      spec->boxes.push_back(bb);
      ClampSet box;
      box.id = "box" + std::to_string(b / 6 + 1);
      const std::string prefix = "bc_box_" + std::to_string(b / 6 + 1) + "_";
      PetscCall(readMotion(prefix, &box));
      PetscBool surface = PETSC_FALSE;
      PetscCall(core::get(opt::boxSurface, &surface, &set, core::ReadContext{prefix.c_str()}));
      box.surfaceOnly = surface == PETSC_TRUE;
      spec->sets.push_back(box);
    }
  }
  PetscCall(core::get(opt::rampSteps, &spec->rampSteps, &set));
  PetscFunctionReturn(0);
}

}  // namespace aries::fem
