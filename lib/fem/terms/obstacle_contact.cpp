#include "fem/terms/obstacle_contact.hpp"

#include "core/errors.hpp"
#include "core/options.hpp"
#include "fem/fem_options.hpp"

#include <sstream>

namespace aries::fem {

using core::collectiveCheck;

PetscErrorCode readObstacleOptions(const Mesh &mesh, ObstacleOptions *o) {
  std::vector<PetscReal> planes, spheres;
  PetscBool hasP = PETSC_FALSE, hasS = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCall(core::get(opt::obstaclePlanes, &planes, &hasP));
  PetscCall(core::get(opt::obstacleSpheres, &spheres, &hasS));
  if (hasP && (planes.empty() || planes.size() % 6))
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
            "option -obstacle_plane takes px,py,pz,nx,ny,nz (a point and the normal towards the free side; 6 "
            "numbers per plane), got %d numbers", (int)planes.size());
  if (hasS && (spheres.empty() || spheres.size() % 4))
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
            "option -obstacle_sphere takes cx,cy,cz,r (4 numbers per sphere), got %d numbers", (int)spheres.size());
  for (size_t k = 0; k < planes.size(); k += 6) {
    kernels::Obstacle ob;
    ob.kind = kernels::Obstacle::Kind::Plane;
    ob.point = Eigen::Vector3d(planes[k], planes[k + 1], planes[k + 2]);
    ob.normal = Eigen::Vector3d(planes[k + 3], planes[k + 4], planes[k + 5]);
    if (!(ob.normal.norm() > 0.0))
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -obstacle_plane: plane %d has a zero normal", (int)(k / 6) + 1);
    ob.normal.normalize();
    o->obstacles.push_back(ob);
  }
  for (size_t k = 0; k < spheres.size(); k += 4) {
    kernels::Obstacle ob;
    ob.kind = kernels::Obstacle::Kind::Sphere;
    ob.point = Eigen::Vector3d(spheres[k], spheres[k + 1], spheres[k + 2]);
    ob.radius = spheres[k + 3];
    if (!(ob.radius > 0.0))
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -obstacle_sphere: sphere %d needs a radius > 0", (int)(k / 4) + 1);
    o->obstacles.push_back(ob);
  }
  if (o->obstacles.empty()) PetscFunctionReturn(0);
  PetscBool set = PETSC_FALSE;
  o->dhat = 1e-2 * mesh.diagonal;
  PetscCall(core::get(opt::contactDhat, &o->dhat, &set));
  PetscCall(core::get(opt::contactStiffness, &o->stiffness, &set));
  o->stiffnessGiven = set;
  PetscFunctionReturn(0);
}

PetscErrorCode ObstacleContact::setup(const Mesh &mesh, const ObstacleOptions &o, double defaultStiffness) {
  MPI_Comm comm;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)mesh.dm, &comm));
  obstacles_ = o.obstacles;
  if (obstacles_.empty()) PetscFunctionReturn(0);
  dhat_ = o.dhat;
  kappa_ = o.stiffnessGiven ? o.stiffness : defaultStiffness;
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
  PetscCall(collectiveCheck(comm, !msg.empty(), msg));
  PetscFunctionReturn(0);
}

void ObstacleContact::addEnergy(const PetscScalar *x, double *energy, double *magnitude) const {
  double e = 0.0;
  for (const auto &vi : verts_) {
    if (!vi.ownedFree()) continue;
    const Eigen::Vector3d xv = Eigen::Map<const Eigen::Vector3d>(x + vi.loc);
    for (const auto &o : obstacles_) e += at(xv, o, kernels::Order::Value).value;
  }
  *energy += e;
  *magnitude += e;  // the barrier is >= 0
}

void ObstacleContact::addGradient(const PetscScalar *x, PetscScalar *g) const {
  for (const auto &vi : verts_) {
    if (!vi.ownedFree()) continue;
    const Eigen::Vector3d xv = Eigen::Map<const Eigen::Vector3d>(x + vi.loc);
    for (const auto &o : obstacles_) {
      const auto d = at(xv, o, kernels::Order::Gradient);
      for (int k = 0; k < 3; ++k) g[vi.loc + k] += d.grad[k];
    }
  }
}

PetscErrorCode ObstacleContact::addHessian(const PetscScalar *x, const HessianAssembly &how, Mat J) const {
  PetscFunctionBeginUser;
  for (const auto &vi : verts_) {
    if (!vi.ownedFree()) continue;
    const Eigen::Vector3d xv = Eigen::Map<const Eigen::Vector3d>(x + vi.loc);
    Eigen::Matrix<double, 3, 3, Eigen::RowMajor> H = Eigen::Matrix3d::Zero();
    for (const auto &o : obstacles_) H += at(xv, o, kernels::Order::Hessian).hess;
    if (H.isZero(0.0)) continue;
    if (how.product()) {  // the vertex's own 3 x 3 block: couples a free component to its held ones (a roller)
      const Eigen::Vector3d y = H * Eigen::Map<const Eigen::Vector3d>(how.productIn + vi.loc);
      for (int k = 0; k < 3; ++k) how.productOut[vi.loc + k] += y[k];
      continue;
    }
    const PetscInt rows[3] = {vi.row(0), vi.row(1), vi.row(2)};
    PetscCall(MatSetValues(J, 3, rows, 3, rows, H.data(), ADD_VALUES));
  }
  PetscFunctionReturn(0);
}

// The barrier's Hessian is PSD (kernels/obstacle_barrier.hpp), so the true and the filtered curvature agree.
void ObstacleContact::addCurvature(const PetscScalar *x, const PetscScalar *const d[], int K, GramMatrix *q) const {
  for (const auto &vi : verts_) {
    if (!vi.ownedFree()) continue;
    const Eigen::Vector3d xv = Eigen::Map<const Eigen::Vector3d>(x + vi.loc);
    Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, kMaxGramDirections> A(3, K);
    for (int k = 0; k < K; ++k) A.col(k) = Eigen::Map<const Eigen::Vector3d>(d[k] + vi.loc);
    for (const auto &o : obstacles_) addGram(A, at(xv, o, kernels::Order::Hessian).hess, K, q);
  }
}

}  // namespace aries::fem
