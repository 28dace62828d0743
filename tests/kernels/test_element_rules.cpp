// Elements at quadrature points (kernels/element_rules.hpp, kernels/elements/): the trilinear hexahedron's rest data
// (partition of unity, F = I at rest, volume, linear fields exact) and the element energy E(x) = sum_q w_q Psi(F_q(x))
// with the gradient and Hessian assembled by addPointGradient / addPointHessian (the code the solver's elastic-cell
// term runs), checked against finite differences of E in the 24 vertex coordinates: for every 3x3 energy (each in its
// singularity modes), on a warped rest hexahedron, at deformed states whose Gauss points see random, inverted and
// near-singular F. The linear tetrahedron (one point) and the quadratic tetrahedron (tet10, 4 points; its rest data
// too) are checked the same way.
#include "kernels/element_rules.hpp"
#include "kernels/elements/hex8.hpp"
#include "kernels/elements/simplex.hpp"
#include "kernels/elements/tet10.hpp"
#include "test_support.hpp"

namespace aries::test {
namespace {

using namespace aries::kernels;
namespace hex = kernels::hex8;
namespace p2 = kernels::tet10;

// A quadratic tetrahedron with straight edges: corners near the unit tet, edge nodes at the edges' midpoints.
Mat<10, 3> straightTet10(Rng &rng, double warp) {
  Mat<10, 3> X = Mat<10, 3>::Zero();
  X.row(1) << 1, 0, 0;
  X.row(2) << 0, 1, 0;
  X.row(3) << 0, 0, 1;
  for (int k = 0; k < 4; ++k) X.row(k) += warp * rng.gaussMat<1, 3>();
  for (int e = 0; e < 6; ++e) X.row(4 + e) = 0.5 * (X.row(p2::kEdges[e][0]) + X.row(p2::kEdges[e][1]));
  return X;
}

// A hexahedron: the unit cube in closure order (kReference mapped to [0,1]^3), every vertex moved by up to `warp`.
Mat<8, 3> warpedHex(Rng &rng, double warp) {
  Mat<8, 3> X;
  for (int v = 0; v < 8; ++v)
    for (int j = 0; j < 3; ++j) X(v, j) = 0.5 * (hex::kReference[v][j] + 1.0) + warp * rng.uniform(-1.0, 1.0);
  return X;
}

template <int NV, int NQ>
struct ElementRest {
  std::array<Mat<NV, 3>, NQ> W;
  std::array<double, NQ> weight;
};

// E, its gradient and its Hessian in the element's positions x (NV x 3, one vertex per row; the FD checker's "F").
template <int NV, int NQ>
Derivs<NV * 3> elementEnergy(const MaterialSetup<3> &s, const ElementRest<NV, NQ> &rest, const Mat<NV, 3> &x,
                             Order order) {
  Derivs<NV * 3> out;
  for (int q = 0; q < NQ; ++q) {
    const Mat<3, 3> F = pointDeformationGradient<3, 3, NV>(x, rest.W[q]);
    const Derivs<9> d = energies::evaluateEnergy<3, 3>(s.m, s.cell, F, order);
    out.value += rest.weight[q] * d.value;
    if (wants(order, Order::Gradient))
      addPointGradient<3, 3, NV>((rest.weight[q] * unflatten<3, 3>(d.grad)).eval(), rest.W[q], &out.grad);
    if (wants(order, Order::Hessian)) {
      Eigen::Matrix<double, NV * 3, NV * 3, Eigen::RowMajor> K = Eigen::Matrix<double, NV * 3, NV * 3, Eigen::RowMajor>::Zero();
      addPointHessian<3, 3, NV>((rest.weight[q] * d.hess).eval(), rest.W[q], &K);
      out.hess += K;
    }
  }
  return out;
}

TEST(ElementRules, HexahedronRestData) {
  Rng rng(seedOf("hex rest data"));
  for (int trial = 0; trial < 20; ++trial) {
    const Mat<8, 3> X = warpedHex(rng, 0.15);
    ElementRest<8, 8> rest;
    const double minDet = hex::restPoints(X, &rest.W, &rest.weight);
    ASSERT_GT(minDet, 0.0);
    double volume = 0.0;
    for (int q = 0; q < 8; ++q) {
      volume += rest.weight[q];
      EXPECT_LT(rest.W[q].colwise().sum().norm(), 1e-13);                                   // sum_v dN_v/dX = 0
      EXPECT_LT((X.transpose() * rest.W[q] - Mat<3, 3>::Identity()).norm(), 1e-13);         // F = I at rest
      const Mat<3, 3> A = Mat<3, 3>::Identity() + 0.3 * rng.gaussMat<3, 3>();             // x = A X: F_q = A
      EXPECT_LT((pointDeformationGradient<3, 3, 8>((X * A.transpose()).eval(), rest.W[q]) - A).norm(), 1e-13);
      EXPECT_NEAR(hex::shapeValues(hex::gaussPoint(q)).sum(), 1.0, 1e-15);
    }
    // The volume of a trilinear hexahedron (2x2x2 Gauss integrates det J, a polynomial of degree 2 per direction,
    // exactly) against the divergence theorem on its 6 bilinear faces: V = 1/3 sum_faces int x . n dA, each face
    // integrated with 4x4 Gauss-Legendre (exact for its cubic integrand).
    const int faces[6][4] = {{0, 1, 2, 3}, {4, 5, 6, 7}, {0, 3, 5, 4}, {1, 7, 6, 2}, {0, 4, 7, 1}, {3, 2, 6, 5}};
    const double g4[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526};
    const double w4[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538};
    double divergence = 0.0;
    for (const auto &f : faces)
      for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b) {
          const double s = g4[a], t = g4[b];
          const Vec<3> p0 = X.row(f[0]), p1 = X.row(f[1]), p2 = X.row(f[2]), p3 = X.row(f[3]);
          const Vec<3> x = 0.25 * ((1 - s) * (1 - t) * p0 + (1 + s) * (1 - t) * p1 + (1 + s) * (1 + t) * p2 +
                                   (1 - s) * (1 + t) * p3);
          const Vec<3> xs = 0.25 * (-(1 - t) * p0 + (1 - t) * p1 + (1 + t) * p2 - (1 + t) * p3);
          const Vec<3> xt = 0.25 * (-(1 - s) * p0 - (1 + s) * p1 + (1 + s) * p2 + (1 - s) * p3);
          divergence += w4[a] * w4[b] * x.dot(xs.cross(xt)) / 3.0;
        }
    // Faces listed with inward or outward normals: the sign is fixed by the cube (volume 1 > 0).
    EXPECT_NEAR(volume, std::abs(divergence), 1e-13) << "trial " << trial;
  }
}

TEST(ElementRules, QuadraticTetrahedronRestData) {
  Rng rng(seedOf("tet10 rest data"));
  for (int trial = 0; trial < 20; ++trial) {
    const Mat<10, 3> X = straightTet10(rng, 0.15);
    ElementRest<10, 4> rest;
    const double minDet = p2::restPoints(X, &rest.W, &rest.weight);
    ASSERT_GT(minDet, 0.0);
    Mat<3, 3> Dm;
    for (int k = 0; k < 3; ++k) Dm.col(k) = (X.row(k + 1) - X.row(0)).transpose();
    const double volume = Dm.determinant() / 6.0;
    // A quadratic field x = A X + (b . X) X is reproduced exactly: F_q = A + (b . X_q) I + X_q b^T.
    const Mat<3, 3> A = Mat<3, 3>::Identity() + 0.3 * rng.gaussMat<3, 3>();
    const Vec<3> b = 0.2 * rng.gaussMat<3, 1>();
    Mat<10, 3> x;
    for (int v = 0; v < 10; ++v) x.row(v) = (A * X.row(v).transpose() + b.dot(X.row(v)) * X.row(v).transpose()).transpose();
    double sum = 0.0;
    Vec<10> consistent = Vec<10>::Zero();
    for (int q = 0; q < 4; ++q) {
      sum += rest.weight[q];
      const Vec<10> N = p2::shapeValues(p2::pointBarycentrics(q));
      EXPECT_NEAR(N.sum(), 1.0, 1e-14);
      consistent += rest.weight[q] * N;
      EXPECT_LT(rest.W[q].colwise().sum().norm(), 1e-12);                            // sum_v dN_v/dX = 0
      EXPECT_LT((X.transpose() * rest.W[q] - Mat<3, 3>::Identity()).norm(), 1e-12);  // F = I at rest
      const Vec<3> Xq = X.transpose() * N;
      const Mat<3, 3> exact = A + b.dot(Xq) * Mat<3, 3>::Identity() + Xq * b.transpose();
      EXPECT_LT((pointDeformationGradient<3, 3, 10>(x, rest.W[q]) - exact).norm(), 1e-12) << "trial " << trial;
    }
    EXPECT_NEAR(sum, volume, 1e-14);
    // The 4-point rule integrates N_i (degree 2) exactly: -V/20 at a corner, V/5 at an edge node; the lumped shares
    // (HRZ) are positive and sum to 1.
    double lumped = 0.0;
    for (int v = 0; v < 10; ++v) {
      EXPECT_NEAR(consistent[v], volume * p2::consistentShare(v), 1e-14);
      EXPECT_GT(p2::lumpedShare(v), 0.0);
      lumped += p2::lumpedShare(v);
    }
    EXPECT_NEAR(lumped, 1.0, 1e-15);
  }
}

// The deformed states: x = A X per vertex plus noise, with A drawn from the F families (random, inverted,
// near-singular), so the Gauss points see F near those families.
template <int NV>
std::vector<std::pair<std::string, Mat<NV, 3>>> deformedStates(const Mat<NV, 3> &X, Rng &rng) {
  std::vector<std::pair<std::string, Mat<NV, 3>>> out;
  auto add = [&](const std::string &name, const Mat<3, 3> &A, double noise) {
    Mat<NV, 3> x = X * A.transpose();
    for (int v = 0; v < NV; ++v) x.row(v) += noise * rng.gaussMat<1, 3>();
    out.push_back({name, x});
  };
  add("random", randomF<3, 3>(rng), 0.05);
  add("inverted", invertedF<3, 3>(rng), 0.03);
  add("near_singular", fromSigma<3, 3>(nearSingularSigma<3, 3>(1.1, 0.8, 0.05), rng), 0.005);
  return out;
}

template <int NV, int NQ>
void checkElement(const char *element, const Mat<NV, 3> &X, const ElementRest<NV, NQ> &rest) {
  for (const EnergyCase &ec : allEnergyCases()) {
    if (ec.shape != ElementShape::Tet) continue;
    Rng rng(seedOf(std::string(element) + " " + caseName(ec)));
    const MaterialSetup<3> s = makeMaterial<3, 3>(ec.kind, ec.mode, rng);
    for (const auto &[family, x] : deformedStates<NV>(X, rng)) {
      auto fn = [&](const Mat<NV, 3> &y, Order order) { return elementEnergy<NV, NQ>(s, rest, y, order); };
      FdExpect ex;
      ex.tol = 1e-5;  // sums of 4 or 8 points' terms: a little more round-off than one point
      expectDerivatives<NV, 3>(fn, x, std::string(element) + " " + caseName(ec) + " " + family,
                               std::string(element) + " " + family, ex);
    }
  }
}

TEST(ElementRules, HexahedronEnergyMatchesFiniteDifferences) {
  Rng rng(seedOf("hex element fd"));
  const Mat<8, 3> X = warpedHex(rng, 0.1);
  ElementRest<8, 8> rest;
  ASSERT_GT(hex::restPoints(X, &rest.W, &rest.weight), 0.0);
  checkElement<8, 8>("hex8", X, rest);
}

TEST(ElementRules, QuadraticTetrahedronEnergyMatchesFiniteDifferences) {
  Rng rng(seedOf("tet10 element fd"));
  const Mat<10, 3> X = straightTet10(rng, 0.1);
  ElementRest<10, 4> rest;
  ASSERT_GT(p2::restPoints(X, &rest.W, &rest.weight), 0.0);
  checkElement<10, 4>("tet10", X, rest);
}

TEST(ElementRules, TetrahedronEnergyMatchesFiniteDifferences) {
  Rng rng(seedOf("tet element fd"));
  Mat<4, 3> X;
  X << 0, 0, 0, 1, 0.1, 0, 0.2, 0.9, 0.1, 0.1, 0.2, 1.1;
  Mat<3, 3> Dm;
  for (int k = 0; k < 3; ++k) Dm.col(k) = (X.row(k + 1) - X.row(0)).transpose();
  const Mat<3, 3> B = Dm.inverse();
  ElementRest<4, 1> rest;
  rest.W[0].row(0) = -B.colwise().sum();
  rest.W[0].bottomRows<3>() = B;
  rest.weight[0] = Dm.determinant() / 6.0;
  checkElement<4, 1>("tet4", X, rest);
}

// The element-type contract (kernels/elements/element_type.hpp), the same checks for every type: at a valid rest cell the
// signed measure is positive and the weights sum to it, sum_v W_q(v) = 0 and F = I at rest (F^T F = I for a triangle
// in 3D), the lumped and consistent shares sum to the measure (lumped ones positive), the output order is a
// permutation; the mirrored cell is inverted (negative measure, the same positive weights); a flat cell is degenerate.
template <class E>
Mat<E::NV, 3> validRest(Rng &rng) {
  if constexpr (E::NV == 8) {
    return warpedHex(rng, 0.1);
  } else if constexpr (E::NV == 10) {
    return straightTet10(rng, 0.1);
  } else {
    Mat<E::NV, 3> X = Mat<E::NV, 3>::Zero();
    for (int k = 1; k < E::NV; ++k) X(k, k - 1) = 1.0;
    for (int k = 0; k < E::NV; ++k) X.row(k).template head<E::C>() += 0.1 * rng.gaussMat<1, E::C>();
    if constexpr (E::R == 3 && E::C == 2) {  // a cloth triangle tilted out of the xy plane
      const Mat<3, 3> turn = Eigen::AngleAxisd(0.7, Vec<3>(1, 2, 0.5).normalized()).toRotationMatrix();
      X = (X * turn.transpose()).eval();
    }
    return X;
  }
}

template <class E>
void checkElementTypeContract() {
  Rng rng(11);
  for (int trial = 0; trial < 5; ++trial) {
    const Mat<E::NV, 3> X = validRest<E>(rng);
    std::array<Mat<E::NV, E::C>, E::NQ> W;
    std::array<double, E::NQ> w;
    double measure = 0.0;
    const double signedMeasure = E::rest(X, E::R == 3 && E::C == 2, &W, &w, &measure);
    ASSERT_GT(signedMeasure, 0.0) << E::kName;
    EXPECT_NEAR(signedMeasure, measure, 1e-14);
    double sum = 0.0, lumped = 0.0, consistent = 0.0;
    for (int q = 0; q < E::NQ; ++q) {
      sum += w[q];
      EXPECT_GT(w[q], 0.0);
      EXPECT_LT(W[q].colwise().sum().norm(), 1e-12) << E::kName;
      const Mat<E::R, E::C> F = X.template leftCols<E::R>().transpose() * W[q];
      if constexpr (E::R == E::C)  // F = I at rest
        EXPECT_LT((F - Mat<E::C, E::C>::Identity()).norm(), 1e-12) << E::kName;
      else  // a triangle in 3D: F maps its frame onto the triangle, F^T F = I
        EXPECT_LT((F.transpose() * F - Mat<E::C, E::C>::Identity()).norm(), 1e-12) << E::kName;
    }
    EXPECT_NEAR(sum, measure, 1e-13 * measure);
    for (int v = 0; v < E::NV; ++v) {
      EXPECT_GT(E::lumpedShare(measure, w, v), 0.0);
      lumped += E::lumpedShare(measure, w, v);
      consistent += E::consistentShare(measure, w, v);
    }
    EXPECT_NEAR(lumped, measure, 1e-13 * measure) << E::kName;
    EXPECT_NEAR(consistent, measure, 1e-13 * measure) << E::kName;
    Mat<E::NV, 3> mirrored = X;
    mirrored.col(0) *= -1.0;
    std::array<double, E::NQ> wm;
    double measureMirrored = 0.0;
    if constexpr (!(E::R == 3 && E::C == 2)) {  // a triangle in 3D has no inside-out: its frame follows its normal
      EXPECT_NEAR(E::rest(mirrored, false, &W, &wm, &measureMirrored), -measure, 1e-13 * measure) << E::kName;
      for (int q = 0; q < E::NQ; ++q) EXPECT_NEAR(wm[q], w[q], 1e-13 * measure);
    }
    Mat<E::NV, 3> flat = X;
    flat.col(E::C - 1).setZero();
    if constexpr (E::R == 3 && E::C == 2) flat.col(2).setZero();  // a triangle in 3D: its vertices on the x axis
    EXPECT_NEAR(E::rest(flat, E::R == 3 && E::C == 2, &W, &wm, &measureMirrored), 0.0, 1e-14) << E::kName;
  }
  // An affine image of the reference cell: the shares are exact fractions of the measure (simplex: 1 / NV each;
  // parallelepiped: 1/8 each; straight P2: HRZ 1/36, 4/27 lumped and -1/20, 1/5 consistent).
  const Mat<E::NV, 3> affine = validRest<E>(rng);
  Mat<E::NV, 3> X = affine;
  if constexpr (E::NV == 8)
    for (int v = 0; v < 8; ++v)
      X.row(v) = (affine.row(0) + 0.5 * (hex::kReference[v][0] + 1) * (affine.row(3) - affine.row(0)) +
                  0.5 * (hex::kReference[v][1] + 1) * (affine.row(1) - affine.row(0)) +
                  0.5 * (hex::kReference[v][2] + 1) * (affine.row(4) - affine.row(0)));
  std::array<Mat<E::NV, E::C>, E::NQ> W;
  std::array<double, E::NQ> w;
  double measure = 0.0;
  ASSERT_GT(E::rest(X, E::R == 3 && E::C == 2, &W, &w, &measure), 0.0) << E::kName;
  for (int v = 0; v < E::NV; ++v) {
    double lumped = 1.0 / E::NV, consistent = 1.0 / E::NV;
    if constexpr (E::NV == 10) {
      lumped = v < 4 ? 1.0 / 36.0 : 4.0 / 27.0;
      consistent = v < 4 ? -1.0 / 20.0 : 1.0 / 5.0;
    }
    EXPECT_NEAR(E::lumpedShare(measure, w, v), lumped * measure, 1e-13 * measure) << E::kName << " node " << v;
    EXPECT_NEAR(E::consistentShare(measure, w, v), consistent * measure, 1e-13 * measure) << E::kName << " node " << v;
  }
  std::array<bool, E::NV> seen{};
  for (int k = 0; k < E::NV; ++k) {
    ASSERT_TRUE(E::outputNode(k) >= 0 && E::outputNode(k) < E::NV) << E::kName << ": output node " << k;
    seen[E::outputNode(k)] = true;
  }
  for (bool b : seen) EXPECT_TRUE(b) << E::kName << ": the output order is no permutation";
  EXPECT_TRUE((std::is_same_v<ElementOf<E::R, E::C, E::NV>, E>)) << E::kName;
}

// A point rule's cell whose det J changes sign between its points (folded, or nodes out of order) is degenerate: 0,
// whatever its net volume; one whose det J is negative at every point is inverted (its volume, negative).
TEST(ElementTypes, FoldedCellsAreDegenerate) {
  std::array<double, 2> mixed = {0.3, -0.1}, negative = {-0.3, -0.1};
  double measure = 0.0;
  EXPECT_EQ(pointRuleMeasure<2>(-0.1, &mixed, &measure), 0.0);
  EXPECT_NEAR(pointRuleMeasure<2>(-0.3, &negative, &measure), -0.4, 1e-15);
  EXPECT_NEAR(measure, 0.4, 1e-15);
  EXPECT_TRUE(negative[0] > 0.0 && negative[1] > 0.0);
  Rng rng(5);
  Mat<8, 3> X = warpedHex(rng, 0.0);
  X.row(0).swap(X.row(1));  // a bow-tie bottom face
  std::array<Mat<8, 3>, 8> W;
  std::array<double, 8> w;
  EXPECT_EQ(Hex8::rest(X, false, &W, &w, &measure), 0.0);
}

// A UV map's rest triangle (planar unknowns, -uv_map): given in 3D, it is measured in its own frame, so its W is the
// flat congruent triangle's up to a rotation of the plane (W W^T agrees) and its measure is its 3D area.
TEST(ElementTypes, PlanarTriangleFromA3DRestShape) {
  Mat<3, 3> flat;
  flat << 0, 0, 0, 1.2, 0.1, 0, 0.3, 0.9, 0;
  const Mat<3, 3> turn = Eigen::AngleAxisd(0.8, Vec<3>(0.3, -1, 0.4).normalized()).toRotationMatrix();
  const Mat<3, 3> tilted = (flat * turn.transpose()).eval();
  std::array<Mat<3, 2>, 1> W, Wflat;
  std::array<double, 1> w, wflat;
  double measure = 0.0, measureFlat = 0.0;
  EXPECT_GT(Tri3Planar::rest(tilted, true, &W, &w, &measure), 0.0);
  EXPECT_GT(Tri3Planar::rest(flat, false, &Wflat, &wflat, &measureFlat), 0.0);
  EXPECT_NEAR(measure, measureFlat, 1e-14);
  EXPECT_LT((W[0] * W[0].transpose() - Wflat[0] * Wflat[0].transpose()).norm(), 1e-12);
}

TEST(ElementTypes, PlanarTriangleContract) { checkElementTypeContract<Tri3Planar>(); }
TEST(ElementTypes, ClothTriangleContract) { checkElementTypeContract<Tri3Cloth>(); }
TEST(ElementTypes, LinearTetrahedronContract) { checkElementTypeContract<Tet4>(); }
TEST(ElementTypes, HexahedronContract) { checkElementTypeContract<Hex8>(); }
TEST(ElementTypes, QuadraticTetrahedronContract) { checkElementTypeContract<Tet10>(); }

}  // namespace
}  // namespace aries::test
