// Cloth bending (quadratic hinges, Bergou et al. 2006) and obstacle contact (log barrier) kernels.
#include "kernels/obstacle_barrier.hpp"
#include "kernels/quadratic_bending.hpp"
#include "test_support.hpp"

namespace aries::test {
namespace {

using kernels::BendingHinge;
using kernels::Obstacle;

// Hinge positions as a 4x3 matrix (row v = vertex v), so the row-major flattening is the kernel's vertex-major one.
Derivs<12> bendingOf(const BendingHinge &h, const Mat<4, 3> &X, double k, Order order) {
  Eigen::Vector3d x[4];
  for (int v = 0; v < 4; ++v) x[v] = X.row(v).transpose();
  return kernels::quadraticBending(h, x, k, order);
}

Mat<4, 3> flatHinge(Rng &rng) {
  Mat<4, 3> X;
  X << 0, 0, 0, 1, 0, 0, rng.uniform(0.2, 0.8), rng.uniform(0.5, 1.0), 0, rng.uniform(0.2, 0.8),
      -rng.uniform(0.5, 1.0), 0;
  return X;
}

BendingHinge hingeOf(const Mat<4, 3> &X) {
  return kernels::bendingHinge(X.row(0).transpose(), X.row(1).transpose(), X.row(2).transpose(), X.row(3).transpose());
}

TEST(QuadraticBending, ZeroForRigidMotionsAndPlanarPlacementsOfTheFlatRestHinge) {
  Rng rng(seedOf("bending rigid"));
  for (int trial = 0; trial < 20; ++trial) {
    const Mat<4, 3> X = flatHinge(rng);
    const BendingHinge h = hingeOf(X);
    EXPECT_LT(bendingOf(h, X, 1.0, Order::Value).value, 1e-26);
    const Eigen::Matrix3d Q = randomRotation<3>(rng);
    const Eigen::RowVector3d t(rng.gauss(), rng.gauss(), rng.gauss());
    Mat<4, 3> Y = X * Q.transpose();
    Y.rowwise() += t;
    EXPECT_LT(bendingOf(h, Y, 1.0, Order::Value).value, 1e-24) << "rigid motion must cost no bending energy";
  }
}

TEST(QuadraticBending, FoldCostsEnergyGrowingWithTheAngle) {
  Rng rng(seedOf("bending fold"));
  const Mat<4, 3> X = flatHinge(rng);
  const BendingHinge h = hingeOf(X);
  double previous = 0.0;
  for (double angle : {0.1, 0.3, 0.6, 1.0}) {  // rotate vertex 3 about the edge (x axis)
    Mat<4, 3> Y = X;
    const Eigen::Vector3d p = X.row(3).transpose();
    Y.row(3) = (Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitX()) * p).transpose();
    const double e = bendingOf(h, Y, 1.0, Order::Value).value;
    EXPECT_GT(e, previous) << "angle " << angle;
    previous = e;
  }
}

TEST(QuadraticBending, DerivativesMatchFiniteDifferencesAndHessianIsPSD) {
  Rng rng(seedOf("bending fd"));
  for (int trial = 0; trial < 10; ++trial) {
    const Mat<4, 3> X = flatHinge(rng);
    const BendingHinge h = hingeOf(X);
    Mat<4, 3> Y = X + 0.2 * rng.gaussMat<4, 3>();
    const double k = rng.uniform(1e-3, 10.0);
    const auto rep = expectDerivatives<4, 3>([&](const Mat<4, 3> &Z, Order o) { return bendingOf(h, Z, k, o); }, Y,
                                             "quadratic bending hinge", "bending");
    const Vec<12> eig = kernels::symmetricEigenvalues<12>(rep.analytic.hess);
    EXPECT_GE(eig[0], -1e-12 * eig.cwiseAbs().maxCoeff());
  }
}

// Exact Hessian of the barrier: the kernel returns its PSD part, without kappa b'(d) hess d; for a sphere
// hess d = (I - n n^T) / |x - c| and kappa b'(d) = grad . n, so the dropped term can be restored from the gradient.
Derivs<3> exactBarrier(const Obstacle &o, const Mat<1, 3> &X, double dhat, double kappa, Order order) {
  const Eigen::Vector3d x = X.transpose();
  Derivs<3> d = kernels::obstacleBarrier(o, x, dhat, kappa, order);
  if (o.kind == Obstacle::Kind::Sphere && wants(order, Order::Hessian)) {
    const Eigen::Vector3d r = x - o.point;
    const Eigen::Vector3d n = r.normalized();
    d.hess += d.grad.dot(n) * (Eigen::Matrix3d::Identity() - n * n.transpose()) / r.norm();
  }
  return d;
}

TEST(ObstacleBarrier, DerivativesMatchFiniteDifferencesForPlaneAndSphere) {
  Rng rng(seedOf("barrier fd"));
  const double dhat = 0.1, kappa = 3.0;
  Obstacle plane;
  plane.point = Eigen::Vector3d(0.1, -0.2, 0.3);
  plane.normal = Eigen::Vector3d(1, 2, 2).normalized();
  Obstacle sphere;
  sphere.kind = Obstacle::Kind::Sphere;
  sphere.point = Eigen::Vector3d(0.5, 0.5, -0.3);
  sphere.radius = 0.4;
  for (int trial = 0; trial < 10; ++trial) {
    const double d = rng.uniform(0.05, 0.9) * dhat;
    const Eigen::Vector3d dir = Eigen::Vector3d(rng.gauss(), rng.gauss(), rng.gauss()).normalized();
    Mat<1, 3> xp = (plane.point + d * plane.normal + 0.3 * dir.cross(plane.normal)).transpose();
    Mat<1, 3> xs = (sphere.point + (sphere.radius + d) * dir).transpose();
    expectDerivatives<1, 3>([&](const Mat<1, 3> &X, Order o) { return exactBarrier(plane, X, dhat, kappa, o); }, xp,
                            "plane barrier", "barrier plane");
    expectDerivatives<1, 3>([&](const Mat<1, 3> &X, Order o) { return exactBarrier(sphere, X, dhat, kappa, o); }, xs,
                            "sphere barrier", "barrier sphere");
    // The returned (projected) Hessian is PSD.
    const Derivs<3> b = kernels::obstacleBarrier(sphere, xs.transpose(), dhat, kappa);
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(b.hess);
    EXPECT_GE(eig.eigenvalues()[0], -1e-12 * eig.eigenvalues().cwiseAbs().maxCoeff());
  }
}

TEST(ObstacleBarrier, ZeroBeyondDhatInfiniteAtContactAndRepulsive) {
  Obstacle plane;  // z = 0, free side +z
  const double dhat = 0.01, kappa = 1.0;
  const Derivs<3> far = kernels::obstacleBarrier(plane, Eigen::Vector3d(0, 0, 2 * dhat), dhat, kappa);
  EXPECT_EQ(far.value, 0.0);
  EXPECT_TRUE(far.grad.isZero(0.0));
  // C2 at dhat: value, slope and curvature vanish continuously.
  const Derivs<3> edge = kernels::obstacleBarrier(plane, Eigen::Vector3d(0, 0, dhat * (1 - 1e-6)), dhat, kappa);
  EXPECT_LT(edge.value, 1e-15);
  EXPECT_LT(edge.grad.norm(), 1e-9);
  EXPECT_LT(edge.hess.norm(), 1e-4);
  const Derivs<3> near = kernels::obstacleBarrier(plane, Eigen::Vector3d(0, 0, 1e-4), dhat, kappa);
  EXPECT_GT(near.value, 0.0);
  EXPECT_LT(near.grad[2], 0.0) << "the energy must decrease away from the obstacle (force pushes out)";
  for (double z : {0.0, -1e-3})
    EXPECT_TRUE(std::isinf(kernels::obstacleBarrier(plane, Eigen::Vector3d(0, 0, z), dhat, kappa).value));
}

}  // namespace
}  // namespace aries::test
