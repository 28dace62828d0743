// The enclosed-volume kernel of follower pressure (kernels/enclosed_volume.hpp): finite differences, and the volume of
// closed surfaces against their exact volume for any reference point.
#include "kernels/enclosed_volume.hpp"
#include "test_support.hpp"

namespace aries::test {
namespace {

// Triangle positions as a 3x3 matrix (row v = vertex v), so the row-major flattening is the kernel's vertex-major one.
Derivs<9> volumeOf(const Mat<3, 3> &X, const Eigen::Vector3d &c, Order order) {
  return kernels::triangleVolume(X.row(0).transpose(), X.row(1).transpose(), X.row(2).transpose(), c, order);
}

TEST(TriangleVolume, DerivativesMatchFiniteDifferences) {
  Rng rng(seedOf("triangle volume fd"));
  for (int trial = 0; trial < 20; ++trial) {
    Mat<3, 3> X;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) X(i, j) = rng.uniform(-1.0, 1.0);
    const Eigen::Vector3d c(rng.uniform(-2.0, 2.0), rng.uniform(-2.0, 2.0), rng.uniform(-2.0, 2.0));
    expectDerivatives<3, 3>([&](const Mat<3, 3> &x, Order o) { return volumeOf(x, c, o); }, X, "triangle volume",
                            "triangle volume");
    // Symmetric and trace-free: the pressure's Hessian is indefinite.
    const Derivs<9> d = volumeOf(X, c, Order::Hessian);
    EXPECT_LT((d.hess - d.hess.transpose()).norm(), 1e-14);
    EXPECT_LT(std::abs(d.hess.trace()), 1e-14);
  }
}

TEST(TriangleVolume, ClosedSurfacesEncloseTheirVolumeFromAnyReferencePoint) {
  Rng rng(seedOf("triangle volume closed"));
  // A tetrahedron with outward faces, and an axis-aligned box of 12 outward triangles.
  const Eigen::Vector3d p[4] = {{0, 0, 0}, {1.5, 0, 0}, {0, 2, 0}, {0, 0, 0.5}};
  const int tetFaces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  const double a = 1.3, b = 0.7, h = 2.1;
  std::vector<Eigen::Vector3d> q;
  for (int k = 0; k < 8; ++k) q.emplace_back(k & 1 ? a : 0.0, k & 2 ? b : 0.0, k & 4 ? h : 0.0);
  const int boxFaces[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                               {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::Vector3d c(rng.uniform(-5.0, 5.0), rng.uniform(-5.0, 5.0), rng.uniform(-5.0, 5.0));
    double tet = 0.0, box = 0.0;
    Eigen::Matrix<double, 12, 1> tetGrad = Eigen::Matrix<double, 12, 1>::Zero();
    for (const auto &f : tetFaces) {
      const Derivs<9> d = kernels::triangleVolume(p[f[0]], p[f[1]], p[f[2]], c);
      tet += d.value;
      for (int i = 0; i < 3; ++i) tetGrad.segment<3>(3 * f[i]) += d.grad.segment<3>(3 * i);
    }
    for (const auto &f : boxFaces) box += kernels::triangleVolume(q[f[0]], q[f[1]], q[f[2]], c).value;
    EXPECT_NEAR(tet, 1.5 * 2.0 * 0.5 / 6.0, 1e-13);
    EXPECT_NEAR(box, a * b * h, 1e-13);
    // dV/dx_v of a closed surface is the vertex's area vector / 3: the apex (0,0,0.5) of the tet moves the volume
    // by the base area / 3 per unit height.
    EXPECT_NEAR(tetGrad[3 * 3 + 2], 0.5 * 1.5 * 2.0 / 3.0, 1e-13);
  }
}

}  // namespace
}  // namespace aries::test
