#include "fem/shape_targets.hpp"

#include "mesh/cell_files.hpp"
#include "core/options.hpp"
#include "fem/fem_options.hpp"

#include <algorithm>
#include <cmath>

namespace aries::fem {


PetscErrorCode TargetField::read(const Mesh &mesh, int dim, bool uniformTargetGiven) {
  MPI_Comm comm;
  std::vector<PetscReal> act;
  std::string file;
  PetscBool hasAct = PETSC_FALSE, hasFile = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)mesh.dm, &comm));
  dim_ = dim;
  comps_ = dim == 3 ? 6 : 3;
  PetscCall(core::get(fem::opt::activation, &act, &hasAct));
  PetscCall(core::get(fem::opt::targetFile, &file, &hasFile));
  if (hasAct && hasFile)
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "options -activation and -target_file both give the shape targets; use one");
  if ((hasAct || hasFile) && uniformTargetGiven)
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s and -target both give the shape targets; use one",
            hasAct ? "-activation" : "-target_file");
  if (hasAct) {
    if (act.empty() || act.size() > 2)
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
              "option -activation takes l1[,l2]: the target stretch along the fiber and across it (got %d numbers)",
              (int)act.size());
    along_ = act[0];
    across_ = act.size() > 1 ? act[1] : 1.0;
    if (!(along_ >= 0.0) || !(across_ >= 0.0) || !std::isfinite(along_) || !std::isfinite(across_))
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -activation: stretches must be finite and >= 0 (got %g,%g)",
              along_, across_);
    source_ = Source::Activation;
  } else if (hasFile) {
    PetscCall(readTargetKeyframeFile(comm, file, mesh.fileCellCount(), mesh.fileCells(), comps_, &times_, &local_));
    ncells_ = static_cast<size_t>(mesh.numCells());
    source_ = Source::Keyframes;
  }
  PetscFunctionReturn(0);
}

Eigen::Matrix3d TargetField::keyframe(size_t k, size_t c) const {
  const double *s = &local_[(k * ncells_ + c) * comps_];
  Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
  if (dim_ == 3) {
    S << s[0], s[3], s[5],  //
        s[3], s[1], s[4],   //
        s[5], s[4], s[2];
  } else {
    S(0, 0) = s[0];
    S(1, 1) = s[1];
    S(0, 1) = S(1, 0) = s[2];
  }
  return S;
}

Eigen::Matrix3d TargetField::at(size_t c, double t, double s, const Eigen::Vector3d &a) const {
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  switch (source_) {
    case Source::Activation: {
      Eigen::Vector3d u = Eigen::Vector3d::Zero();
      u.head(dim_) = a.head(dim_);
      Eigen::Matrix3d P = I;
      P.bottomRightCorner(3 - dim_, 3 - dim_).setZero();  // planar elements: the 2x2 block is used
      const Eigen::Matrix3d St = along_ * u * u.transpose() + across_ * (P - u * u.transpose());
      return I + s * (St - I);
    }
    case Source::Keyframes: {
      if (t <= times_.front()) return keyframe(0, c);
      if (t >= times_.back()) return keyframe(times_.size() - 1, c);
      const size_t k = std::upper_bound(times_.begin(), times_.end(), t) - times_.begin();  // times_[k-1] < t < times_[k]
      const double w = (t - times_[k - 1]) / (times_[k] - times_[k - 1]);
      return (1.0 - w) * keyframe(k - 1, c) + w * keyframe(k, c);
    }
    case Source::Material:
      break;
  }
  return I;
}

namespace {

template <int C>
class ShapeTargetSource final : public CellFieldSource<C> {
 public:
  PetscErrorCode setup(const Mesh &mesh, const std::vector<char> &applies,
                       std::vector<energies::CellData<C>> *data) override {
    PetscBool uniform = PETSC_FALSE;
    PetscFunctionBeginUser;
    PetscCall(PetscOptionsHasName(nullptr, nullptr, "-target", &uniform));
    PetscCall(targets_.read(mesh, C, uniform));
    if (targets_.source() != TargetField::Source::Material) update(0.0, 0.0, applies, data);  // the rest step
    PetscFunctionReturn(0);
  }
  bool varies() const override { return targets_.loadDependent() || targets_.timeDependent(); }
  void update(double time, double load, const std::vector<char> &applies,
              std::vector<energies::CellData<C>> *data) const override {
    for (size_t c = 0; c < applies.size(); ++c) {
      if (!applies[c]) continue;
      Eigen::Vector3d a = Eigen::Vector3d::Zero();
      a.head<C>() = (*data)[c].a;
      (*data)[c].target = targets_.at(c, time, load, a).template topLeftCorner<C, C>();
    }
  }
  std::unique_ptr<CellFieldSource<C>> clone() const override { return std::make_unique<ShapeTargetSource<C>>(*this); }

 private:
  TargetField targets_;
};

}  // namespace

template <int C>
std::unique_ptr<CellFieldSource<C>> makeShapeTargetSource() {
  return std::make_unique<ShapeTargetSource<C>>();
}
template std::unique_ptr<CellFieldSource<2>> makeShapeTargetSource<2>();
template std::unique_ptr<CellFieldSource<3>> makeShapeTargetSource<3>();

}  // namespace aries::fem
