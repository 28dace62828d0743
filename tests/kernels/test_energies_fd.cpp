// Finite-difference tests of PK1 and Hessian for EVERY energy: all 14 kinds x every
// singularity mode they support x every element shape they support (53 cases), each over the standard F families
// of test_support.hpp (random, inverted, stretched/compressed, near alpha = 0 at normalized alpha 0.1 / 0.02) plus,
// per mode, F placed where the singularity fix is active:
//   mollifier: absolute alpha in the blend band [eps, 3 eps] = [1e-3, 3e-3] and below eps (proxy region),
//   barrier:   absolute alpha inside (0, eps) = (0, 1e-2), where kappa b(alpha) is active.
#include "test_support.hpp"

namespace aries::test {
namespace {

using namespace aries::kernels;

// Where the singularity fixes are active. alpha is absolute, so for tets the elements are shrunk (singular values
// ~0.25, 0.13) to put these alpha values at normalized alpha ~0.04 .. 0.3, where FD can resolve the raw I4
// Hessian. At unit scale the same absolute alpha means alpha_n ~ 3e-4 .. 3e-3, where the closed-form I4 Hessian itself
// carries round-off of ~10-100 eps / alpha_n^4 relative (1e-5 .. 1e-1; see test_reference_svd.cpp,
// ClosedFormI4DerivativesNearSingular), so FD at 1e-6 would test round-off, not correctness. 2D elements have no such
// amplification (f = |(F00+F11, F10-F01)|) and are tested at unit scale.
template <int R, int C>
std::vector<Sample<R, C>> energyFamilies(const EnergyCase &ec) {
  std::vector<Sample<R, C>> out = standardFamilies<R, C>(seedOf(caseName(ec)));
  Rng rng(seedOf(caseName(ec) + " singular"));
  const double scale = (R == 3 && C == 3) ? 0.2 : 1.0;
  if (ec.mode == SingularityMode::Mollifier) {
    for (double a : {1.2e-3, 2e-3, 2.8e-3})
      out.push_back({"mollifier_band", "mollifier band alpha=" + sci(a), alphaF<R, C>(rng, a, false, scale)});
    out.push_back({"mollifier_proxy", "below mollifier eps alpha=5e-4", alphaF<R, C>(rng, 5e-4, false, scale)});
  }
  if (ec.mode == SingularityMode::Barrier)
    for (double a : {2e-3, 5e-3, 9e-3})
      out.push_back({"barrier_active", "barrier active alpha=" + sci(a), alphaF<R, C>(rng, a, false, scale)});
  return out;
}

// kim_aa's sign S(I4) must not flip inside the FD stencil: every basis direction needs |I4(u_k)| well away from 0.
template <int R, int C>
bool kimSignsStable(const MaterialSetup<C> &s, const std::vector<Sample<R, C>> &samples) {
  for (const auto &smp : samples) {
    const auto ctx = makeRootContext<R, C>(smp.F, Order::Value);
    for (int k = 0; k < C; ++k) {
      const Vec<C> u = s.m.basis.row(k).template head<C>().transpose();
      if (std::abs(stretchInvariantValue<R, C>(ctx, fiberTensor<C>(u))) < 0.02 * smp.F.norm()) return false;
    }
  }
  return true;
}

class EnergyFD : public ::testing::TestWithParam<EnergyCase> {};

TEST_P(EnergyFD, PK1AndHessianMatchFiniteDifferences) {
  const EnergyCase ec = GetParam();
  withShape(ec.shape, [&](auto Rc, auto Cc) {
    constexpr int R = decltype(Rc)::value, C = decltype(Cc)::value;
    const auto samples = energyFamilies<R, C>(ec);
    Rng rng(seedOf(caseName(ec) + " material"));
    MaterialSetup<C> setup = makeMaterial<R, C>(ec.kind, ec.mode, rng);
    if (ec.kind == EnergyKind::KimAA)
      for (int tries = 0; !kimSignsStable<R, C>(setup, samples); ++tries) {
        ASSERT_LT(tries, 1000) << "no material basis keeps kim_aa's I4 signs away from 0";
        setup = makeMaterial<R, C>(ec.kind, ec.mode, rng);
      }
    // The requested mode survived finalize (energies without I4/I6 terms have only 'none').
    ASSERT_EQ(setup.m.singularity.mode, ec.mode);
    const auto fn = energyFn<R, C>(setup);
    int barrierActive = 0, mollifierBand = 0;
    for (const auto &smp : samples) {
      // Below the mollifier's eps every I4/I6 is the constant proxy (0): bw461 / bw46s consist of nothing else, so
      // they are exactly flat there -- checked explicitly instead of by FD.
      const bool flat = smp.family == "mollifier_proxy" &&
                        (ec.kind == EnergyKind::Bw461 || ec.kind == EnergyKind::Bw46s);
      FdExpect ex;
      ex.allowZeroGradient = ex.allowZeroHessian = flat;
      const auto rep = expectDerivatives<R, C>(fn, smp.F, caseName(ec) + " on " + smp.label,
                                               caseName(ec) + " " + smp.family, ex);
      if (flat) {
        const double offset = ec.kind == EnergyKind::Bw46s ? setup.cell.a.dot(setup.cell.b) : 0.0;
        EXPECT_NEAR(rep.analytic.value, setup.m.mu1 + setup.m.mu2 * offset * offset, 1e-14);
        EXPECT_EQ(rep.analytic.grad.norm(), 0.0);
        EXPECT_EQ(rep.analytic.hess.norm(), 0.0);
      }
      const double alpha = rootValue(smp.F).alpha;
      if (ec.mode == SingularityMode::Barrier && alpha < setup.m.singularity.barrier.eps) {
        // Non-vacuous: the barrier really contributes here (energy differs from the mode-'none' energy).
        Material none = setup.m;
        none.singularity.mode = SingularityMode::None;
        const double raw = energies::evaluateEnergy<R, C>(none, setup.cell, smp.F, Order::Value).value;
        EXPECT_GT(rep.analytic.value - raw, 0.0) << "barrier inactive at alpha=" << alpha;
        ++barrierActive;
      }
      if (ec.mode == SingularityMode::Mollifier && alpha >= 1e-3 && alpha <= 3e-3) ++mollifierBand;
    }
    if (ec.mode == SingularityMode::Barrier) {
      EXPECT_GE(barrierActive, 3);
    }
    if (ec.mode == SingularityMode::Mollifier) {
      EXPECT_EQ(mollifierBand, 3);
    }
  });
}

INSTANTIATE_TEST_SUITE_P(AllEnergies, EnergyFD, ::testing::ValuesIn(allEnergyCases()),
                         [](const ::testing::TestParamInfo<EnergyCase> &info) { return caseName(info.param); });

// The case list really covers the whole matrix: 14 kinds, 53 (kind, shape, mode) combinations.
TEST(EnergyFDCoverage, AllKindsShapesAndModes) {
  const auto cases = allEnergyCases();
  EXPECT_EQ(cases.size(), 53u);
  for (EnergyKind k : kAllKinds) {
    int n = 0;
    for (const auto &c : cases) n += (c.kind == k);
    EXPECT_GT(n, 0) << energies::energyName(k);
  }
}

}  // namespace
}  // namespace aries::test
