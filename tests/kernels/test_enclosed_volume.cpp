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


// Random positions of a face's nodes (rows), near a unit patch so the faces are not degenerate.
template <int K>
Mat<K, 3> randomFace(Rng &rng) {
  Mat<K, 3> X;
  for (int i = 0; i < K; ++i)
    for (int j = 0; j < 3; ++j) X(i, j) = rng.uniform(-1.0, 1.0);
  return X;
}

template <class Face>
void expectFaceDerivatives(const char *name) {
  constexpr int K = Face::kNodes;
  Rng rng(seedOf(std::string("face volume fd ") + name));
  for (int trial = 0; trial < 10; ++trial) {
    const Mat<K, 3> X = randomFace<K>(rng);
    const Eigen::Vector3d c(rng.uniform(-2.0, 2.0), rng.uniform(-2.0, 2.0), rng.uniform(-2.0, 2.0));
    expectDerivatives<K, 3>([&](const Mat<K, 3> &x, Order o) { return kernels::faceVolume<Face>(x, c, o); }, X,
                            std::string("face volume ") + name, std::string("face volume ") + name);
    // Trace-free like the triangle's: the follower pressure's Hessian is indefinite on every face type.
    const Derivs<3 * K> d = kernels::faceVolume<Face>(X, c);
    EXPECT_LT(std::abs(d.hess.trace()), 1e-13 * (1.0 + d.hess.norm())) << name;
  }
}

TEST(FaceVolume, DerivativesMatchFiniteDifferences) {
  expectFaceDerivatives<kernels::face::Tri3>("tri3");
  expectFaceDerivatives<kernels::face::Quad4>("quad4");
  expectFaceDerivatives<kernels::face::Tri6>("tri6");
}

TEST(FaceVolume, LinearTriangleAndStraightQuadraticTriangleEqualTheTriangleKernel) {
  Rng rng(seedOf("face volume tri"));
  for (int trial = 0; trial < 10; ++trial) {
    const Mat<3, 3> X = randomFace<3>(rng);
    const Eigen::Vector3d c(rng.uniform(-2.0, 2.0), rng.uniform(-2.0, 2.0), rng.uniform(-2.0, 2.0));
    const Derivs<9> ref = volumeOf(X, c, Order::Hessian), tri3 = kernels::faceVolume<kernels::face::Tri3>(X, c);
    EXPECT_NEAR(tri3.value, ref.value, 1e-14);
    EXPECT_LT((tri3.grad - ref.grad).norm(), 1e-14);
    EXPECT_LT((tri3.hess - ref.hess).norm(), 1e-14);
    // The same triangle as a 6-node one with its edge nodes at the edges' middles: the same volume.
    Mat<6, 3> X6;
    X6.topRows<3>() = X;
    X6.row(3) = (X.row(0) + X.row(1)) / 2;
    X6.row(4) = (X.row(1) + X.row(2)) / 2;
    X6.row(5) = (X.row(2) + X.row(0)) / 2;
    EXPECT_NEAR(kernels::faceVolume<kernels::face::Tri6>(X6, c, Order::Value).value, ref.value, 1e-14);
  }
}

TEST(FaceVolume, ClosedCurvedSurfacesEncloseTheirExactVolume) {
  Rng rng(seedOf("face volume closed"));
  // A box of 6 outward quadrangles, warped by a trilinear map x = X + eps X_x X_y X_z e: its faces stay bilinear (the
  // map is bilinear on each face), and the enclosed volume is the integral of det(grad x) over the box.
  const double a = 1.3, b = 0.7, h = 2.1;
  std::vector<Eigen::Vector3d> q;
  for (int k = 0; k < 8; ++k) q.emplace_back(k & 1 ? a : 0.0, k & 2 ? b : 0.0, k & 4 ? h : 0.0);
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  // A sphere of radius r as an octahedron of 8 quadratic triangles whose 6 corners and 12 edge nodes lie on it, and
  // a straight-edged octahedron (volume 4 r^3 / 3).
  const double r = 0.9;
  const Eigen::Vector3d v[6] = {{r, 0, 0}, {-r, 0, 0}, {0, r, 0}, {0, -r, 0}, {0, 0, r}, {0, 0, -r}};
  const int tris[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::Vector3d c(rng.uniform(-5.0, 5.0), rng.uniform(-5.0, 5.0), rng.uniform(-5.0, 5.0));
    double box = 0.0, flat = 0.0;
    for (const auto &f : quads) {
      Mat<4, 3> X;
      for (int i = 0; i < 4; ++i) X.row(i) = q[f[i]].transpose();
      box += kernels::faceVolume<kernels::face::Quad4>(X, c, Order::Value).value;
    }
    EXPECT_NEAR(box, a * b * h, 1e-13);
    for (const auto &f : tris) {
      Mat<6, 3> X;
      for (int i = 0; i < 3; ++i) X.row(i) = v[f[i]].transpose();
      for (int e = 0; e < 3; ++e) X.row(3 + e) = (X.row(e) + X.row((e + 1) % 3)) / 2;
      flat += kernels::faceVolume<kernels::face::Tri6>(X, c, Order::Value).value;
    }
    EXPECT_NEAR(flat, 4.0 * r * r * r / 3.0, 1e-13);
  }
  // Warped box: x = X + eps (X_x X_y X_z / (a b h)) (1, 1, 1) is trilinear, so each face is an exact bilinear patch of
  // its mapped corners; V = int det(I + eps grad phi) dX, computed here by a 4x4x4 Gauss rule (exact: degree <= 3 per
  // coordinate).
  const double eps = 0.3, g[4] = {-0.861136311594053, -0.339981043584856, 0.339981043584856, 0.861136311594053},
               wg[4] = {0.347854845137454, 0.652145154862546, 0.652145154862546, 0.347854845137454};
  auto map = [&](const Eigen::Vector3d &X) {
    return (X + Eigen::Vector3d::Constant(eps * X[0] * X[1] * X[2] / (a * b * h))).eval();
  };
  double exact = 0.0;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k) {
        const Eigen::Vector3d X(a * (1 + g[i]) / 2, b * (1 + g[j]) / 2, h * (1 + g[k]) / 2);
        const Eigen::Vector3d grad(X[1] * X[2], X[0] * X[2], X[0] * X[1]);
        Eigen::Matrix3d J = Eigen::Matrix3d::Identity() + Eigen::Vector3d::Ones() * (eps / (a * b * h)) * grad.transpose();
        exact += wg[i] * wg[j] * wg[k] * J.determinant() * a * b * h / 8;
      }
  double warped = 0.0;
  for (const auto &f : quads) {
    Mat<4, 3> X;
    for (int i = 0; i < 4; ++i) X.row(i) = map(q[f[i]]).transpose();
    warped += kernels::faceVolume<kernels::face::Quad4>(X, Eigen::Vector3d(0.1, -0.2, 0.3), Order::Value).value;
  }
  EXPECT_GT(std::abs(warped - a * b * h), 1e-2);  // the warp changes the volume, so the check is not vacuous
  EXPECT_NEAR(warped, exact, 1e-12);
}

// The unit sphere as 6-node triangles: each octant split k x k, every corner on the sphere; the edge nodes projected
// onto it too (curved: the P2 surface) or at the chords' middles (flat). Each triangle, outward (corners 1, 2 and the
// edges 01, 20 swapped where needed), goes to fn.
template <class Fn>
void forEachSphereTriangle(int k, bool curved, Fn fn) {
  for (int sx = -1; sx <= 1; sx += 2)
    for (int sy = -1; sy <= 1; sy += 2)
      for (int sz = -1; sz <= 1; sz += 2) {
        auto P = [&](double i, double j) {  // grid point (i, j) of the octant's face, projected on the sphere
          return Eigen::Vector3d(sx * (k - i - j) / k, sy * i / k, sz * j / k).normalized().eval();
        };
        for (int i = 0; i < k; ++i)
          for (int j = 0; i + j < k; ++j)
            for (int up = 0; up < 2; ++up) {
              if (up && i + j + 1 >= k) continue;
              const double down[3][2] = {{1.0 * i, 1.0 * j}, {i + 1.0, 1.0 * j}, {1.0 * i, j + 1.0}};
              const double upper[3][2] = {{i + 1.0, j + 1.0}, {1.0 * i, j + 1.0}, {i + 1.0, 1.0 * j}};
              const double(*c)[2] = up ? upper : down;
              Mat<6, 3> X;
              for (int n = 0; n < 3; ++n) X.row(n) = P(c[n][0], c[n][1]).transpose();
              for (int e = 0; e < 3; ++e) {
                const int f = (e + 1) % 3;
                X.row(3 + e) = curved ? P((c[e][0] + c[f][0]) / 2, (c[e][1] + c[f][1]) / 2).transpose()
                                      : ((X.row(e) + X.row(f)) / 2).eval();
              }
              const Eigen::Vector3d n = (X.row(1) - X.row(0)).cross(X.row(2) - X.row(0)).transpose();
              if (n.dot(X.row(0).transpose()) < 0) {
                X.row(1).swap(X.row(2));
                X.row(3).swap(X.row(5));
              }
              fn(X);
            }
      }
}

TEST(FaceVolume, CurvedQuadraticSphereEnclosesTheBallBeyondSecondOrder) {
  // The curved 6-node triangles (the P2 surface) enclose 4 pi / 3 at order 3 or more; the flat ones through the same
  // corners at order 2. Every piece carries the face kernel.
  auto sphereVolume = [](int k, bool curved) {
    double V = 0.0;
    forEachSphereTriangle(k, curved, [&](const Mat<6, 3> &X) {
      V += kernels::faceVolume<kernels::face::Tri6>(X, Eigen::Vector3d::Zero(), Order::Value).value;
    });
    return V;
  };
  const double ball = 4.0 * M_PI / 3.0;
  const double curved4 = std::abs(sphereVolume(4, true) - ball), curved8 = std::abs(sphereVolume(8, true) - ball);
  const double flat4 = std::abs(sphereVolume(4, false) - ball), flat8 = std::abs(sphereVolume(8, false) - ball);
  EXPECT_GT(std::log2(curved4 / curved8), 2.8);
  EXPECT_NEAR(std::log2(flat4 / flat8), 2.0, 0.2);
  EXPECT_LT(curved8, flat8 / 10);
}

TEST(FaceAreaMoments, SumToTheAreaVectorAndSplitAsTheConsistentLoad) {
  Rng rng(seedOf("face area moments"));
  // A flat triangle: each corner carries A n / 3; its 6-node form carries 0 at the corners and A n / 3 at edge nodes.
  const Mat<3, 3> X = randomFace<3>(rng);
  const Eigen::Vector3d an = 0.5 * (X.row(1) - X.row(0)).cross(X.row(2) - X.row(0)).transpose();
  const Mat<3, 3> m3 = kernels::faceAreaMoments<kernels::face::Tri3>(X);
  for (int i = 0; i < 3; ++i) EXPECT_LT((m3.row(i).transpose() - an / 3).norm(), 1e-14);
  Mat<6, 3> X6;
  X6.topRows<3>() = X;
  for (int e = 0; e < 3; ++e) X6.row(3 + e) = (X.row(e) + X.row((e + 1) % 3)) / 2;
  const Mat<6, 3> m6 = kernels::faceAreaMoments<kernels::face::Tri6>(X6);
  for (int i = 0; i < 3; ++i) EXPECT_LT(m6.row(i).norm(), 1e-14);
  for (int i = 3; i < 6; ++i) EXPECT_LT((m6.row(i).transpose() - an / 3).norm(), 1e-14);
  // A parallelogram: a quarter of its area vector at each corner; a warped quadrangle: the moments sum to the area
  // vector int n dA, which for any patch is half the cross product of its diagonals.
  Mat<4, 3> P;
  P.row(0) = X.row(0);
  P.row(1) = X.row(1);
  P.row(2) = X.row(1) + X.row(2) - X.row(0);
  P.row(3) = X.row(2);
  const Mat<4, 3> mp = kernels::faceAreaMoments<kernels::face::Quad4>(P);
  for (int i = 0; i < 4; ++i) EXPECT_LT((mp.row(i).transpose() - an / 2).norm(), 1e-14);
  const Mat<4, 3> W = randomFace<4>(rng);
  const Eigen::Vector3d diag = 0.5 * (W.row(2) - W.row(0)).cross(W.row(3) - W.row(1)).transpose();
  EXPECT_LT((kernels::faceAreaMoments<kernels::face::Quad4>(W).colwise().sum().transpose() - diag).norm(), 1e-14);
}

TEST(FaceAreaShares, FlatFacesSplitTheirAreaAsTheConsistentLoadAndCurvedOnesConverge) {
  Rng rng(seedOf("face area shares"));
  const Mat<3, 3> X = randomFace<3>(rng);
  const double area = 0.5 * (X.row(1) - X.row(0)).cross(X.row(2) - X.row(0)).norm();
  const Vec<3> s3 = kernels::faceAreaShares<kernels::face::Tri3>(X);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(s3[i], area / 3, 1e-14);
  Mat<6, 3> X6;
  X6.topRows<3>() = X;
  for (int e = 0; e < 3; ++e) X6.row(3 + e) = (X.row(e) + X.row((e + 1) % 3)) / 2;
  const Vec<6> s6 = kernels::faceAreaShares<kernels::face::Tri6>(X6);
  for (int i = 0; i < 3; ++i) EXPECT_LT(std::abs(s6[i]), 1e-14);
  for (int i = 3; i < 6; ++i) EXPECT_NEAR(s6[i], area / 3, 1e-14);
  // The unit sphere's area 4 pi: the curved 6-node triangles converge at order > 2.8, the flat ones at order 2.
  auto sphereArea = [](int k, bool curved) {
    double A = 0.0;
    forEachSphereTriangle(k, curved,
                          [&](const Mat<6, 3> &X) { A += kernels::faceAreaShares<kernels::face::Tri6>(X).sum(); });
    return A;
  };
  const double sphere = 4.0 * M_PI;
  const double curved4 = std::abs(sphereArea(4, true) - sphere), curved8 = std::abs(sphereArea(8, true) - sphere);
  const double flat4 = std::abs(sphereArea(4, false) - sphere), flat8 = std::abs(sphereArea(8, false) - sphere);
  EXPECT_GT(std::log2(curved4 / curved8), 2.8);
  EXPECT_NEAR(std::log2(flat4 / flat8), 2.0, 0.2);
  EXPECT_LT(curved8, flat8 / 10);
}

}  // namespace
}  // namespace aries::test
