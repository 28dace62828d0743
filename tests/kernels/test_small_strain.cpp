// Small-strain limit (docs/energies.md, moduli): iarap = mu |F - R|^2 + lambda/2 (J - 1)^2 linearizes to linear elasticity
// sigma = 2 mu eps + lambda tr(eps) I with the Lame parameters of (E, nu) (material.hpp's convention).
//
// Checked at strain 1e-4 (tension and compression) with E = 1e4, nu = 0.3, to 1%:
//  * tets, uniaxial stress: F = diag(1 + e, l, l) with the lateral stretches l relaxed (Newton on the energy's own
//    PK1/Hessian) to zero lateral stress; P11 / e = E and (l - 1) / e = -nu. Also along a random material direction
//    (F = Q diag(...) Q^T, stresses compared in the rotated frame), which exercises the off-diagonal entries.
//  * tets, simple shear F = I + g e1 e2^T: P12 / g = mu; pure dilation F = (1 + e) I: P11 / e = 3 lambda + 2 mu.
//  * planar triangles: the 2x2 energy is 3D iarap restricted to in-plane motion, i.e. PLANE STRAIN (eps_33 = 0) with
//    the 3D Lame parameters. Uniaxial in-plane stress (sigma_22 = 0, sigma_33 free) then gives
//      sigma_22 = lambda e11 + (lambda + 2 mu) e22 = 0   ->  e22 / e11 = -lambda / (lambda + 2 mu) = -nu / (1 - nu)
//      sigma_11 / e11 = (lambda + 2 mu) - lambda^2 / (lambda + 2 mu) = 4 mu (lambda + mu) / (lambda + 2 mu)
//                     = E / (1 - nu^2),
//    both checked; plus simple shear P12 / g = mu and in-plane dilation P11 / e = 2 (lambda + mu).
// iarap_lin and arap_svd (the same energy) and every iarap singularity mode are run through the same checks.
#include "test_support.hpp"

namespace aries::test {
namespace {

using namespace aries::kernels;

constexpr double kE = 1e4, kNu = 0.3, kStrain = 1e-4, kTol = 0.01;

template <int D>
Material isotropic(EnergyKind kind, SingularityMode mode) {
  Material m;
  m.kind = kind;
  m.mu = energies::lameMu(kE, kNu);
  m.lambda = energies::lameLambda(kE, kNu);
  m.singularity.mode = mode;
  EXPECT_EQ(energies::finalizeMaterial(m, D == 3 ? ElementShape::Tet : ElementShape::Planar), "");
  return m;
}

std::vector<Material> isotropicMaterials(int dim) {
  std::vector<Material> out;
  for (SingularityMode mode : kAllModes)
    out.push_back(dim == 3 ? isotropic<3>(EnergyKind::Iarap, mode) : isotropic<2>(EnergyKind::Iarap, mode));
  for (EnergyKind k : {EnergyKind::IarapLin, EnergyKind::ArapSvd})
    out.push_back(dim == 3 ? isotropic<3>(k, SingularityMode::None) : isotropic<2>(k, SingularityMode::None));
  return out;
}

// Uniaxial stress along the first axis of the frame Q: F = Q diag(1 + e, l_2, ..) Q^T with the lateral stretches
// solved so that the lateral diagonal stresses of Q^T P Q vanish. Returns (P11 in the frame, lateral stretches).
template <int D>
std::pair<double, Vec<D>> uniaxial(const Material &m, double e, const Mat<D, D> &Q) {
  Vec<D> s = Vec<D>::Ones();
  s[0] = 1.0 + e;
  const CellData<D> cell;
  double P11 = 0.0;
  for (int it = 0; it < 30; ++it) {
    const Mat<D, D> F = Q * s.asDiagonal() * Q.transpose();
    const auto d = energies::evaluateEnergy<D, D>(m, cell, F);
    const Mat<D, D> Pf = Q.transpose() * unflatten<D, D>(d.grad) * Q;  // stress in the frame
    P11 = Pf(0, 0);
    // Derivative of the frame stress diagonal w.r.t. the stretches s_k: H contracted with q_i q_i^T (x) q_k q_k^T.
    Eigen::Matrix<double, D - 1, 1> g;
    Eigen::Matrix<double, D - 1, D - 1> H;
    for (int a = 1; a < D; ++a) {
      g[a - 1] = Pf(a, a);
      const Vec<D * D> qa = flatten<D, D>(Mat<D, D>(Q.col(a) * Q.col(a).transpose()));
      for (int b = 1; b < D; ++b) {
        const Vec<D * D> qb = flatten<D, D>(Mat<D, D>(Q.col(b) * Q.col(b).transpose()));
        H(a - 1, b - 1) = qa.dot(d.hess * qb);
      }
    }
    if (g.norm() < 1e-12 * kE * std::abs(e)) break;
    const Eigen::Matrix<double, D - 1, 1> step = H.ldlt().solve(-g);
    for (int a = 1; a < D; ++a) s[a] += step[a - 1];
  }
  return {P11, s};
}

template <int D>
void uniaxialStress() {
  const double nu = kNu;
  // 3D: E and nu; plane strain: E / (1 - nu^2) and nu / (1 - nu).
  const double Eeff = D == 3 ? kE : kE / (1.0 - nu * nu);
  const double nuEff = D == 3 ? nu : nu / (1.0 - nu);
  Rng rng(seedOf("uniaxial " + std::to_string(D)));
  for (const Material &m : isotropicMaterials(D))
    for (double e : {kStrain, -kStrain})
      for (int frame = 0; frame < 2; ++frame) {
        const Mat<D, D> Q = frame == 0 ? Mat<D, D>::Identity() : randomRotation<D>(rng);
        const auto [P11, s] = uniaxial<D>(m, e, Q);
        const std::string what = std::string(energies::energyName(m.kind)) + " (" +
                                 energies::singularityName(m.singularity.mode) + ") strain " + std::to_string(e) +
                                 (frame ? " rotated frame" : "");
        EXPECT_NEAR(P11 / e / Eeff, 1.0, kTol) << "effective modulus: " << what;
        for (int a = 1; a < D; ++a)
          EXPECT_NEAR((s[a] - 1.0) / e / (-nuEff), 1.0, kTol) << "lateral contraction: " << what;
        recordError(std::string("small strain |P11/e/E_eff - 1| ") + (D == 3 ? "3D" : "plane strain"),
                    std::abs(P11 / e / Eeff - 1.0));
        recordError(std::string("small strain |lateral/(-nu_eff e) - 1| ") + (D == 3 ? "3D" : "plane strain"),
                    std::abs((s[1] - 1.0) / e / (-nuEff) - 1.0));
      }
}

TEST(SmallStrain, UniaxialStressGivesYoungsModulusAndPoisson_Tet) { uniaxialStress<3>(); }
TEST(SmallStrain, UniaxialStressGivesPlaneStrainModuli_Planar) { uniaxialStress<2>(); }

template <int D>
void shearAndDilation() {
  const double mu = energies::lameMu(kE, kNu), lambda = energies::lameLambda(kE, kNu);
  for (const Material &m : isotropicMaterials(D)) {
    const CellData<D> cell;
    const std::string what = std::string(energies::energyName(m.kind)) + " (" +
                             energies::singularityName(m.singularity.mode) + ")";
    Mat<D, D> F = Mat<D, D>::Identity();
    F(0, 1) = kStrain;
    const auto s = energies::evaluateEnergy<D, D>(m, cell, F, Order::Gradient);
    EXPECT_NEAR(s.grad[1] / kStrain / mu, 1.0, kTol) << "shear modulus: " << what;
    const auto v = energies::evaluateEnergy<D, D>(m, cell, Mat<D, D>((1.0 + kStrain) * Mat<D, D>::Identity()),
                                                  Order::Gradient);
    // Dilation: sigma_11 = (D lambda + 2 mu) e (3D: 3 lambda + 2 mu = 3K; plane strain: 2 lambda + 2 mu).
    EXPECT_NEAR(v.grad[0] / kStrain / (D * lambda + 2.0 * mu), 1.0, kTol) << "dilation: " << what;
    // Energy density matches the linear one: Psi = mu |eps|^2 ... = mu g^2 / 2 for simple shear.
    EXPECT_NEAR(s.value / (0.5 * mu * kStrain * kStrain), 1.0, kTol) << "shear energy: " << what;
  }
}

TEST(SmallStrain, ShearModulusAndDilation_Tet) { shearAndDilation<3>(); }
TEST(SmallStrain, ShearModulusAndDilation_Planar) { shearAndDilation<2>(); }

// The Lame conversion used everywhere (3D / plane strain).
TEST(SmallStrain, LameParametersFromYoungAndPoisson) {
  const double mu = energies::lameMu(kE, kNu), lambda = energies::lameLambda(kE, kNu);
  EXPECT_NEAR(mu, kE / 2.6, 1e-9);
  EXPECT_NEAR(lambda, kE * 0.3 / (1.3 * 0.4), 1e-9);
  EXPECT_NEAR(mu * (3 * lambda + 2 * mu) / (lambda + mu), kE, 1e-9);  // E from (mu, lambda)
  EXPECT_NEAR(lambda / (2 * (lambda + mu)), kNu, 1e-12);              // nu from (mu, lambda)
}

}  // namespace
}  // namespace aries::test
