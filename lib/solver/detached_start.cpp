// Static solves from a synthetic start (-initial scramble, invert, collapse_*): the body is first relaxed without its
// supports, then moved rigidly onto them, and only then solved with them (-static_detached_start, on by default).
//
// Why: from a scrambled start the supported solve first gathers the body into its rest shape in whatever orientation
// the scramble suggests, then has to turn it back into its supports' orientation. Turned by a large angle relative
// to its supports, the body is twisted in the few cell layers next to them; Newton unwinds such a twist slowly (tens
// of short steps; the hand test mesh, seed 3: 87 updates), and where several supports hold separate limbs (a
// quadruped pinned at its feet) the twisted limbs can be a local minimum of the elastic energy: the solve converges
// to an equilibrium far from rest. Without supports nothing can twist: the body relaxes to its rest shape up to a
// rigid motion, and the rigid motion that best fits its supported vertices onto their prescribed positions (Kabsch)
// puts it onto them. The supported solve then starts from there (at rest when the supports hold the rest shape).
//
// The relaxation itself runs in two stages (-static_detached_shape_first, on by default): first with the volume terms
// lambda/2 (J - J0)^2 off, then with the full energy from there. A scrambled cell is stretched by about L / h (L the
// body's size, h its cells'), and J grows like the cube of the stretch, so the volume term grows like its sixth
// power: Newton on such a term shrinks the stretch by a fixed factor per update (a power s^6 loses 1/5 of s per
// Newton step), and the gathering takes more updates the finer the mesh (camel, scramble seed 2: 8 updates on the
// 1.8k-tet test mesh, 17 on the 16.6k-tet default one). The stretch terms mu |F - R|^2 grow like the square of the
// stretch: they gather the body in one update. For the ARAP family their minimum is already the rest shape up to a
// rigid motion (F = R in every cell), so the second stage starts at rest and only certifies it (0 updates); where
// the cells' rest shapes do not fit together (shape targets) it finishes the relaxation. The shape stage runs only
// where the stretch terms alone fix each cell's shape (Discretization::stretchTermsFixShape: not for aniso with
// fewer than three directions, whose remaining strain only the volume term holds, nor for caricature, whose I4 term
// moves the minimum); one that fails leaves the second stage the synthetic start.
// The Newton updates, linear solves and history of all solves are the step's.
#include "solver/simulation.hpp"

#include "kernels/svd_polar.hpp"

namespace aries::solver {

namespace {

// The proper rigid motion y = R p + t that best maps the points p_i onto q_i (least squares; Kabsch: R is the
// closest rotation to the cross-covariance sum (q_i - q)(p_i - p)^T), from the owned supported vertices of every
// rank. One point: a translation.
PetscErrorCode fitRigidMotion(MPI_Comm comm, const std::vector<PetscInt> &vertices, const std::vector<double> &from,
                              const std::vector<double> &to, Eigen::Matrix3d *R, Eigen::Vector3d *t) {
  PetscFunctionBeginUser;
  double sums[16] = {0.0};  // count, sum p, sum q, sum q p^T
  for (PetscInt v : vertices) {
    const Eigen::Vector3d p(from[3 * v], from[3 * v + 1], from[3 * v + 2]);
    const Eigen::Vector3d q(to[3 * v], to[3 * v + 1], to[3 * v + 2]);
    sums[0] += 1.0;
    for (int i = 0; i < 3; ++i) {
      sums[1 + i] += p[i];
      sums[4 + i] += q[i];
      for (int j = 0; j < 3; ++j) sums[7 + 3 * i + j] += q[i] * p[j];
    }
  }
  double total[16];
  PetscCallMPI(MPI_Allreduce(sums, total, 16, MPI_DOUBLE, MPI_SUM, comm));
  const double n = total[0];
  const Eigen::Vector3d pMean = Eigen::Vector3d(total[1], total[2], total[3]) / n;
  const Eigen::Vector3d qMean = Eigen::Vector3d(total[4], total[5], total[6]) / n;
  Eigen::Matrix3d cross;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) cross(i, j) = total[7 + 3 * i + j] - n * qMean[i] * pMean[j];
  *R = kernels::svdRotation<3, 3>(cross);
  *t = qMean - *R * pMean;
  PetscFunctionReturn(0);
}

// Positions given per local vertex (3 each) into the owned free dofs of a global vector.
PetscErrorCode setFreePositions(const fem::Kinematics &kin, const std::vector<double> &xyz, Vec xGlobal) {
  PetscScalar *x;
  PetscInt lo;
  PetscFunctionBeginUser;
  PetscCall(VecGetOwnershipRange(xGlobal, &lo, nullptr));
  PetscCall(VecGetArray(xGlobal, &x));
  kin.forEachOwnedFreeVertex([&](PetscInt local, PetscInt, const PetscInt *rows, const Eigen::Vector3d &) {
    for (int i = 0; i < 3; ++i)
      if (rows[i] >= 0) x[rows[i] - lo] = xyz[3 * local + i];
  });
  PetscCall(VecRestoreArray(xGlobal, &x));
  PetscFunctionReturn(0);
}

}  // namespace

PetscErrorCode Simulation::detachedStart(NewtonResult *acc) {
  MPI_Comm comm;
  PetscFunctionBeginUser;
  if (disc_->dofsPerVertex() != 3 || disc_->numBoundaryVerticesGlobal() == 0) PetscFunctionReturn(0);
  PetscCall(PetscObjectGetComm((PetscObject)x_, &comm));
  std::vector<PetscInt> supported;  // the relaxed body is placed on the vertices prescribed in every component
  disc_->kinematics().ownedSupportedVertices(&supported);
  PetscInt numSupported = static_cast<PetscInt>(supported.size());
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &numSupported, 1, MPIU_INT, MPI_SUM, comm));
  if (numSupported == 0) PetscFunctionReturn(0);  // symmetry planes or rollers only: nothing to place it on
  // The detached body: the same mesh on a DM clone (its own DOF layout), no supports, elastic terms only.
  fem::Mesh mesh = disc_->mesh();  // (copies the metadata; the DM is replaced before anything can destroy it)
  mesh.dm = nullptr;
  PetscCall(DMClone(disc_->dm(), &mesh.dm));
  std::unique_ptr<fem::Discretization> detached;
  PetscCall(disc_->detachedCopy(mesh, &detached));
  fem::StepState step = disc_->step();
  step.dt = 0.0;
  step.prediction = nullptr;
  PetscCall(detached->setStep(step));

  Vec local, y;
  std::vector<double> start, relaxed;
  PetscCall(DMGetLocalVector(disc_->dm(), &local));
  PetscCall(localState(local));
  PetscCall(disc_->kinematics().vertexPositions(local, &start));  // the supported vertices at their prescribed positions
  PetscCall(DMRestoreLocalVector(disc_->dm(), &local));
  PetscCall(DMCreateGlobalVector(detached->dm(), &y));
  PetscCall(setFreePositions(detached->kinematics(), start, y));

  NewtonResult result;
  {
    NewtonSolver newton;
    NewtonOptions options;  // the main solver's, overridden by -detached_newton_tol, ...
    PetscCall(readNewtonOptions(false, &opts_.newton, "detached_", &options));
    PetscCall(newton.setup(*detached, options, false, 0.0, &newton_, "detached_", true));
    if (opts_.detachedShapeFirst) PetscCall(solveShapeFirst(*detached, newton, y, 0.0, 0.0, acc));  // shape_first.cpp
    PetscCall(newton.solve(y, &result));
  }
  *acc += result;
  if (result.converged()) {
    PetscCall(DMGetLocalVector(detached->dm(), &local));
    PetscCall(VecSet(local, 0.0));
    PetscCall(DMGlobalToLocal(detached->dm(), y, INSERT_VALUES, local));
    PetscCall(detached->kinematics().vertexPositions(local, &relaxed));
    PetscCall(DMRestoreLocalVector(detached->dm(), &local));
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
    PetscCall(fitRigidMotion(comm, supported, relaxed, start, &R, &t));
    for (size_t v = 0; 3 * v < relaxed.size(); ++v) {
      const Eigen::Vector3d p = R * Eigen::Vector3d(relaxed[3 * v], relaxed[3 * v + 1], relaxed[3 * v + 2]) + t;
      for (int i = 0; i < 3; ++i) relaxed[3 * v + i] = p[i];
    }
    PetscCall(setFreePositions(disc_->kinematics(), relaxed, x_));
  }  // else the supported solve starts from the synthetic state as it would without this phase
  PetscCall(VecDestroy(&y));
  PetscFunctionReturn(0);
}

}  // namespace aries::solver
