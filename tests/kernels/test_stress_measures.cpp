// Output stress and strain measures (kernels/stress_measures.hpp) against closed-form states: a uniaxial stretch
// of iarap (P = 2 mu (F - R) with lambda = 0; bw46 on cloth), a uniform scaling (J, stretches, Green-Lagrange), a
// rotated state (Cauchy rotates with the body, Green-Lagrange does not move), an inverted element (signed
// stretches), and cloth / planar triangles reported in the mesh's 3D frame.
#include "kernels/stress_measures.hpp"
#include "test_support.hpp"

namespace aries::test {
namespace {

using energies::EnergyKind;
using energies::Material;

Material iarapMaterial(double E, double nu, energies::ElementShape shape) {
  Material m;
  m.kind = EnergyKind::Iarap;
  m.mu = energies::lameMu(E, nu);
  m.lambda = energies::lameLambda(E, nu);
  EXPECT_EQ(energies::finalizeMaterial(m, shape), "");
  return m;
}

template <int R, int C>
Mat<R, C> pk1(const Material &m, const Mat<R, C> &F) {
  const auto d = energies::evaluateEnergy<R, C>(m, energies::CellData<C>{}, F, Order::Gradient);
  return kernels::unflatten<R, C>(d.grad);
}

TEST(StressMeasures, UniaxialStretchOfIarapWithoutLateralContraction) {
  const Material m = iarapMaterial(1e4, 0.0, energies::ElementShape::Tet);
  const double s = 1.2;
  const Mat<3, 3> F = Vec<3>(1.0, 1.0, s).asDiagonal();
  const auto q = kernels::stressMeasures<3, 3>(F, pk1<3, 3>(m, F), Mat<3, 3>::Identity());
  const double szz = 2.0 * m.mu * (s - 1.0);  // P = 2 mu (F - I), sigma = P F^T / J
  Mat<3, 3> expected = Mat<3, 3>::Zero();
  expected(2, 2) = szz;
  EXPECT_LT((q.pk1 - expected).norm(), 1e-9 * szz);
  EXPECT_LT((q.cauchy - expected).norm(), 1e-9 * szz);
  EXPECT_NEAR(q.vonMises, szz, 1e-9 * szz);
  EXPECT_NEAR(q.J, s, 1e-15);
  EXPECT_NEAR(q.greenLagrange(2, 2), 0.5 * (s * s - 1.0), 1e-15);
  EXPECT_NEAR(q.greenLagrange.norm(), 0.5 * (s * s - 1.0), 1e-15);
  EXPECT_LT((q.principalStretches - Vec<3>(s, 1.0, 1.0)).norm(), 1e-14);
  EXPECT_LT((q.deformationGradient - F).norm(), 1e-15);
}

TEST(StressMeasures, UniformScalingHasJCubedAndHydrostaticStress) {
  const Material m = iarapMaterial(1e4, 0.3, energies::ElementShape::Tet);
  const double a = 0.9;
  const Mat<3, 3> F = a * Mat<3, 3>::Identity();
  const auto q = kernels::stressMeasures<3, 3>(F, pk1<3, 3>(m, F), Mat<3, 3>::Identity());
  EXPECT_NEAR(q.J, a * a * a, 1e-15);
  EXPECT_LT((q.principalStretches - Vec<3>::Constant(a)).norm(), 1e-14);
  EXPECT_LT((q.greenLagrange - 0.5 * (a * a - 1.0) * Mat<3, 3>::Identity()).norm(), 1e-15);
  // hydrostatic: sigma = p I, no deviator
  EXPECT_NEAR(q.vonMises, 0.0, 1e-9 * std::abs(q.cauchy(0, 0)));
  EXPECT_LT((q.cauchy - q.cauchy(0, 0) * Mat<3, 3>::Identity()).norm(), 1e-9 * std::abs(q.cauchy(0, 0)));
  // p = dPsi/dJ: Psi = mu |F - I|^2 + lambda/2 (J - 1)^2 = 3 mu (a - 1)^2 + ..., P = 2 mu (a - 1) I + lambda (J-1) cof
  const double J = a * a * a, P = 2.0 * m.mu * (a - 1.0) + m.lambda * (J - 1.0) * a * a;
  EXPECT_NEAR(q.cauchy(0, 0), P * a / J, 1e-9 * std::abs(P));
}

TEST(StressMeasures, CauchyRotatesWithTheBodyGreenLagrangeDoesNot) {
  Rng rng(seedOf("stress measures rotation"));
  const Material m = iarapMaterial(1e4, 0.3, energies::ElementShape::Tet);
  for (int k = 0; k < 20; ++k) {
    const Mat<3, 3> F = Mat<3, 3>::Identity() + 0.2 * rng.gaussMat<3, 3>();
    const Mat<3, 3> Q = randomRotation<3>(rng);
    const auto a = kernels::stressMeasures<3, 3>(F, pk1<3, 3>(m, F), Mat<3, 3>::Identity());
    const Mat<3, 3> QF = Q * F;
    const auto b = kernels::stressMeasures<3, 3>(QF, pk1<3, 3>(m, QF), Mat<3, 3>::Identity());
    const double scale = a.cauchy.norm() + 1.0;
    EXPECT_LT((b.cauchy - Q * a.cauchy * Q.transpose()).norm(), 1e-9 * scale);
    EXPECT_NEAR(b.vonMises, a.vonMises, 1e-9 * scale);
    EXPECT_LT((b.greenLagrange - a.greenLagrange).norm(), 1e-12);
    EXPECT_LT((b.principalStretches - a.principalStretches).norm(), 1e-12);
    EXPECT_NEAR(b.J, a.J, 1e-12);
    // the Cauchy stress is symmetric for a rotation-invariant energy
    EXPECT_LT((a.cauchy - a.cauchy.transpose()).norm(), 1e-9 * scale);
  }
}

TEST(StressMeasures, InvertedElementHasANegativeSmallestStretch) {
  const Mat<3, 3> F = Vec<3>(1.1, 0.8, -0.5).asDiagonal();
  const auto q = kernels::stressMeasures<3, 3>(F, Mat<3, 3>::Zero(), Mat<3, 3>::Identity());
  EXPECT_NEAR(q.J, -0.44, 1e-15);
  EXPECT_LT((q.principalStretches - Vec<3>(1.1, 0.8, -0.5)).norm(), 1e-14);
  const auto flat = kernels::stressMeasures<3, 3>(Mat<3, 3>(Vec<3>(1.0, 1.0, 0.0).asDiagonal()), Mat<3, 3>::Identity(),
                                                  Mat<3, 3>::Identity());
  EXPECT_TRUE(std::isnan(flat.cauchy(0, 0)));  // J = 0: no Cauchy stress
}

TEST(StressMeasures, ClothTriangleInTheRestPlaneFrame) {
  // A triangle in the plane x + z = const: orthonormal chart e1 = y, e2 = (x - z)/sqrt 2. Stretch 1.3 along e2.
  Mat<3, 2> Frest;
  Frest.col(0) = Vec<3>(0, 1, 0);
  Frest.col(1) = Vec<3>(1, 0, -1) / std::sqrt(2.0);
  Material m;  // bw46: iarap_lin's shear term with mu1 / 2 (Baraff-Witkin's stretch as ARAP, cloth only)
  m.kind = EnergyKind::Bw46;
  m.mu1 = 1000.0;
  m.mu2 = 500.0;
  ASSERT_EQ(energies::finalizeMaterial(m, energies::ElementShape::Cloth), "");
  const double s = 1.3;
  const Mat<3, 2> F = Frest * Vec<2>(1.0, s).asDiagonal();  // the deformed triangle stays in that plane
  const auto q = kernels::stressMeasures<3, 2>(F, pk1<3, 2>(m, F), Frest);
  EXPECT_NEAR(q.J, s, 1e-14);
  EXPECT_LT((q.principalStretches - Vec<3>(s, 1.0, 1.0)).norm(), 1e-14);
  const Vec<3> e2 = Frest.col(1);
  EXPECT_LT((q.greenLagrange - 0.5 * (s * s - 1.0) * e2 * e2.transpose()).norm(), 1e-14);
  EXPECT_LT((q.deformationGradient * e2 - s * e2).norm(), 1e-14);
  // the membrane stress acts along e2 only and is that of the 2D state
  const Mat<3, 3> sigma = q.cauchy;
  EXPECT_LT((sigma - (sigma(0, 0) + sigma(2, 2)) * e2 * e2.transpose()).norm(), 1e-9 * sigma.norm());
  EXPECT_NEAR(e2.dot(sigma * e2), m.mu1 * (s - 1.0), 1e-9 * m.mu1);  // P = mu1 (F - R), sigma = P F^T / J
}

TEST(StressMeasures, PlanarTriangleIsPlaneStress) {
  const Material m = iarapMaterial(1e4, 0.0, energies::ElementShape::Planar);
  Mat<3, 2> Frest = Mat<3, 2>::Zero();
  Frest(0, 0) = Frest(1, 1) = 1.0;
  const double s = 0.9;
  const Mat<2, 2> F = Vec<2>(s, 1.0).asDiagonal();
  const auto q = kernels::stressMeasures<2, 2>(F, pk1<2, 2>(m, F), Frest);
  EXPECT_NEAR(q.cauchy(0, 0), 2.0 * m.mu * (s - 1.0), 1e-9 * m.mu);
  EXPECT_NEAR(q.cauchy.norm(), std::abs(q.cauchy(0, 0)), 1e-9 * m.mu);
  EXPECT_NEAR(q.vonMises, std::abs(q.cauchy(0, 0)), 1e-9 * m.mu);  // uniaxial plane stress
  EXPECT_LT((q.principalStretches - Vec<3>(1.0, s, 1.0)).norm(), 1e-14);
  EXPECT_NEAR(q.J, s, 1e-15);
}

}  // namespace
}  // namespace aries::test
