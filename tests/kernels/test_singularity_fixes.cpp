// The two singularity fixes (paper Sec. 4: mollifier, aberration barrier) and the baseline's flaw:
//  * mollified I4 / I6: FD inside the blend band [eps, 3 eps] and below eps; exactly the proxy below eps and exactly
//    the raw invariant above 3 eps; C1 (in fact C2) across alpha = eps and alpha = 3 eps along a smooth path,
//  * aberration barrier: FD inside (0, eps); b, b', b'' vanish at eps; b -> +inf as alpha -> 0+; +inf at alpha <= 0,
//  * kim_aa (Kim 2019 Psi_AA) jumps by 4 mu sqrt(I5) where I4 of a basis direction changes sign; iarap does not,
//  * PSD projection: PSD output, unchanged for PSD input; absolute-value filtering flips the negative eigenvalues.
#include "kernels/aberration_barrier.hpp"
#include "kernels/mollifier.hpp"
#include "kernels/psd_projection.hpp"
#include "test_support.hpp"

namespace aries::test {
namespace {

using namespace aries::kernels;

// Tets are shrunk so that the absolute alpha of the mollifier band sits at normalized alpha ~0.04 .. 0.1, where FD
// can resolve the raw I4 Hessian (see energyFamilies in test_energies_fd.cpp for the reason).
template <int R, int C>
constexpr double bandScale() {
  return (R == 3 && C == 3) ? 0.2 : 1.0;
}

// ---- mollifier: FD in and below the band -------------------------------------------------------------------------

template <int R, int C>
void mollifierFd() {
  Rng rng(seedOf(std::string("mollifier fd ") + shapeTag<R, C>()));
  const MollifierParams p;  // eps = 1e-3, proxy 0
  ASSERT_EQ(p.eps, 1e-3);
  ASSERT_EQ(p.proxy, 0.0);
  for (double alpha : {1.05e-3, 1.5e-3, 2e-3, 2.5e-3, 2.95e-3, 4e-3}) {
    const Mat<R, C> F = alphaF<R, C>(rng, alpha, false, bandScale<R, C>());
    const Vec<C> a = randomUnit<C>(rng), b = randomUnit<C>(rng);
    ASSERT_NEAR(rootValue(F).alpha / alpha, 1.0, 1e-6);
    const std::string fam = alpha <= 3e-3 ? "band" : "above_band";
    expectDerivatives<R, C>([&](const Mat<R, C> &G, Order o) { return mollifiedI4<R, C>(G, a, p, o); }, F,
                            std::string("mollified I4 ") + shapeTag<R, C>() + " alpha=" + std::to_string(alpha),
                            std::string("mollified I4 ") + shapeTag<R, C>() + " " + fam);
    expectDerivatives<R, C>([&](const Mat<R, C> &G, Order o) { return mollifiedI6<R, C>(G, a, b, p, o); }, F,
                            std::string("mollified I6 ") + shapeTag<R, C>() + " alpha=" + std::to_string(alpha),
                            std::string("mollified I6 ") + shapeTag<R, C>() + " " + fam);
    // Inside the band the blend is a genuine mix: strictly between the proxy and the raw value.
    if (alpha < 3e-3) {
      const double raw = invariantI4<R, C>(F, a, Order::Value).value, mol = mollifiedI4<R, C>(F, a, p).value;
      EXPECT_LT(std::abs(mol), std::abs(raw)) << "alpha=" << alpha;
      EXPECT_GT(std::abs(mol), 0.0) << "alpha=" << alpha;
    }
  }
  // Random F (far above the band) for the other families.
  for (const auto &s : standardFamilies<R, C>(seedOf(std::string("mollifier standard ") + shapeTag<R, C>()))) {
    const Vec<C> a = randomUnit<C>(rng);
    expectDerivatives<R, C>([&](const Mat<R, C> &G, Order o) { return mollifiedI4<R, C>(G, a, p, o); }, s.F,
                            std::string("mollified I4 ") + shapeTag<R, C>() + " " + s.label,
                            std::string("mollified I4 ") + shapeTag<R, C>() + " " + s.family);
  }
}

TEST(Mollifier, FiniteDifferencesInAndAroundBand_3x3) { mollifierFd<3, 3>(); }
TEST(Mollifier, FiniteDifferencesInAndAroundBand_2x2) { mollifierFd<2, 2>(); }
TEST(Mollifier, FiniteDifferencesInAndAroundBand_3x2) { mollifierFd<3, 2>(); }

// Below eps: exactly the proxy c tr(D), zero derivatives (the raw invariant is not even evaluated). Above 3 eps:
// bit-identical to the raw invariant.
template <int R, int C>
void mollifierExactOutsideBand() {
  Rng rng(seedOf(std::string("mollifier exact ") + shapeTag<R, C>()));
  for (double proxy : {0.0, 0.37}) {
    MollifierParams p;
    p.proxy = proxy;
    for (double alpha : {1e-7, 1e-4, 5e-4, 9.9e-4}) {
      const Mat<R, C> F = alphaF<R, C>(rng, alpha, false);
      const Vec<C> a = randomUnit<C>(rng), b = randomUnit<C>(rng);
      ASSERT_LT(rootValue(F).alpha, p.eps);
      const auto m4 = mollifiedI4<R, C>(F, a, p), m6 = mollifiedI6<R, C>(F, a, b, p);
      EXPECT_EQ(m4.value, proxy * fiberTensor<C>(a).trace());  // c tr(D); tr(aa^T) = |a|^2 = 1 to round-off
      EXPECT_EQ(m6.value, proxy * crossFiberTensor<C>(a, b).trace());
      EXPECT_DOUBLE_EQ(m6.value, proxy * a.dot(b));  // tr((ab^T + ba^T)/2) = a.b
      EXPECT_EQ(m4.grad.norm() + m4.hess.norm() + m6.grad.norm() + m6.hess.norm(), 0.0);
      // Non-vacuous: the raw invariant at the same F is different and has large derivatives.
      const auto raw = invariantI4<R, C>(F, a);
      EXPECT_GT(std::abs(raw.value - proxy), 1e-3);
      EXPECT_GT(raw.grad.norm(), 0.1);
    }
    for (double alpha : {3.0001e-3, 5e-3, 0.1}) {
      const Mat<R, C> F = alphaF<R, C>(rng, alpha, false);
      const Vec<C> a = randomUnit<C>(rng), b = randomUnit<C>(rng);
      ASSERT_GT(rootValue(F).alpha, 3.0 * p.eps);
      const auto m4 = mollifiedI4<R, C>(F, a, p), r4 = invariantI4<R, C>(F, a);
      const auto m6 = mollifiedI6<R, C>(F, a, b, p), r6 = invariantI6<R, C>(F, a, b);
      EXPECT_EQ(m4.value, r4.value);
      EXPECT_EQ(m4.grad, r4.grad);
      EXPECT_EQ(m4.hess, r4.hess);
      EXPECT_EQ(m6.value, r6.value);
      EXPECT_EQ(m6.grad, r6.grad);
      EXPECT_EQ(m6.hess, r6.hess);
    }
  }
}

TEST(Mollifier, ExactlyProxyBelowEpsAndRawAbove3Eps_3x3) { mollifierExactOutsideBand<3, 3>(); }
TEST(Mollifier, ExactlyProxyBelowEpsAndRawAbove3Eps_2x2) { mollifierExactOutsideBand<2, 2>(); }
TEST(Mollifier, ExactlyProxyBelowEpsAndRawAbove3Eps_3x2) { mollifierExactOutsideBand<3, 2>(); }

// -mollifier_measure scale_free: the band's coordinate alpha (I_C / C)^(-k/2) equals alpha where I_C = C, does not
// change when F is scaled, has consistent derivatives, and the mollified I4 / I6 on it pass FD inside its band.
template <int R, int C>
void scaleFreeMollifier() {
  Rng rng(seedOf(std::string("mollifier scale-free ") + shapeTag<R, C>()));
  MollifierParams p;
  p.measure = MollifierMeasure::ScaleFree;
  p.eps = 0.3;  // a band the paper's alpha would put at 1e-3
  auto coordinate = [&](const Mat<R, C> &G, Order o) { return mollifierCoordinate(makeRootContext<R, C>(G, o), p); };
  for (const auto &smp : standardFamilies<R, C>(seedOf(std::string("scale-free standard ") + shapeTag<R, C>()))) {
    const double a = rootValue(smp.F).alpha, c = mollifierCoordinate<R, C>(smp.F, a, p);
    for (double t : {0.25, 3.0}) {
      const Mat<R, C> G = t * smp.F;
      const double cg = mollifierCoordinate<R, C>(G, rootValue(G).alpha, p);
      EXPECT_NEAR(cg / c, 1.0, 1e-9) << smp.label << " t=" << t;
    }
    const Mat<R, C> unit = smp.F * std::sqrt(C / smp.F.squaredNorm());  // I_C = C: the coordinate is alpha
    const double au = rootValue(unit).alpha, cu = mollifierCoordinate<R, C>(unit, au, p);
    EXPECT_NEAR(cu, au, 1e-12 * (1.0 + au));
    expectDerivatives<R, C>(coordinate, smp.F, std::string("scale-free alpha ") + shapeTag<R, C>() + " " + smp.label,
                            std::string("scale-free alpha ") + shapeTag<R, C>() + " " + smp.family);
  }
  int inBand = 0;
  for (double target : {0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 1.0, 1.2}) {
    const Mat<R, C> F = alphaF<R, C>(rng, target, false);
    const double c = mollifierCoordinate<R, C>(F, rootValue(F).alpha, p);
    if (!(c > p.eps * 1.02 && c < 3.0 * p.eps * 0.98)) continue;
    ++inBand;
    const Vec<C> a = randomUnit<C>(rng), b = randomUnit<C>(rng);
    const std::string what = std::string(" ") + shapeTag<R, C>() + " coordinate=" + std::to_string(c);
    expectDerivatives<R, C>([&](const Mat<R, C> &G, Order o) { return mollifiedI4<R, C>(G, a, p, o); }, F,
                            "scale-free mollified I4" + what, std::string("scale-free mollified I4 ") + shapeTag<R, C>());
    expectDerivatives<R, C>([&](const Mat<R, C> &G, Order o) { return mollifiedI6<R, C>(G, a, b, p, o); }, F,
                            "scale-free mollified I6" + what, std::string("scale-free mollified I6 ") + shapeTag<R, C>());
    // a genuine blend: strictly between the proxy 0 and the raw value
    const double raw = invariantI4<R, C>(F, a, Order::Value).value, mol = mollifiedI4<R, C>(F, a, p).value;
    EXPECT_LT(std::abs(mol), std::abs(raw)) << what;
    EXPECT_GT(std::abs(mol), 0.0) << what;
  }
  EXPECT_GE(inBand, 2) << "too few samples inside the scale-free band";
}

TEST(Mollifier, ScaleFreeMeasure_3x3) { scaleFreeMollifier<3, 3>(); }
TEST(Mollifier, ScaleFreeMeasure_2x2) { scaleFreeMollifier<2, 2>(); }
TEST(Mollifier, ScaleFreeMeasure_3x2) { scaleFreeMollifier<3, 2>(); }

TEST(Mollifier, SmootherstepProfile) {
  // S2(0) = 0, S2(1) = 1, S2' = S2'' = 0 at both ends, S2(1/2) = 1/2, and derivatives consistent with FD.
  EXPECT_EQ(smootherstep(0.0).value, 0.0);
  EXPECT_EQ(smootherstep(1.0).value, 1.0);
  EXPECT_DOUBLE_EQ(smootherstep(0.5).value, 0.5);
  EXPECT_DOUBLE_EQ(smootherstep(0.5).d1, 30.0 / 16.0);
  for (double x : {0.0, 1.0}) {
    EXPECT_EQ(smootherstep(x).d1, 0.0);
    EXPECT_EQ(smootherstep(x).d2, 0.0);
  }
  for (double x : {0.1, 0.3, 0.7, 0.95}) {
    const double h = 1e-6;
    EXPECT_NEAR(smootherstep(x).d1, (smootherstep(x + h).value - smootherstep(x - h).value) / (2 * h), 1e-8);
    EXPECT_NEAR(smootherstep(x).d2, (smootherstep(x + h).d1 - smootherstep(x - h).d1) / (2 * h), 1e-7);
  }
  // Blend weight maps [eps, 3 eps] onto [0, 1].
  EXPECT_EQ(mollifierBlend(1e-3, 1e-3).value, 0.0);
  EXPECT_EQ(mollifierBlend(3e-3, 1e-3).value, 1.0);
  EXPECT_DOUBLE_EQ(mollifierBlend(2e-3, 1e-3).value, 0.5);
}

// ---- continuity along a path ----------------------------------------------------------------------------------------

// Value and PK1 jumps across s* along F(s): J(t) = |g(s* + t) - g(s* - t)| for t = t0, t0/10, ...
struct JumpSequence {
  std::vector<double> t, value, grad, hess;
};

template <int R, int C, class Fn, class Path>
JumpSequence jumps(Fn &&fn, Path &&path, double sStar, double t0, int n) {
  JumpSequence js;
  double t = t0;
  for (int k = 0; k < n; ++k, t *= 0.1) {
    const auto p = fn(path(sStar + t), Order::Hessian), m = fn(path(sStar - t), Order::Hessian);
    js.t.push_back(t);
    js.value.push_back(std::abs(p.value - m.value));
    js.grad.push_back((p.grad - m.grad).norm());
    js.hess.push_back((p.hess - m.hess).norm());
  }
  return js;
}

// "Jump -> 0 linearly or better" for J(t) = |g(s* + t) - g(s* - t)|, t = t0, t0/10, ...: a function continuous at
// s* has J(t) = O(t), a discontinuous one J(t) -> |jump| > 0. Asserted: J(t)/t stays bounded as t -> 0 (<= 3x its
// value at the second step; the first, largest step may still be dominated by curvature), the asymptotic decrease per
// step is the step ratio 0.1 (last three ratios <= 0.15, above a round-off floor), and the last jump is tiny compared
// with the function's scale.
bool jumpsVanish(const std::vector<double> &j, const std::vector<double> &t, double scale, std::string *why) {
  std::ostringstream os;
  for (size_t k = 1; k < j.size(); ++k)
    if (!(j[k] / t[k] <= 3.0 * j[1] / t[1] + 1e-11 * scale / t[k])) os << "J(t)/t grows at t=" << t[k] << "; ";
  for (size_t k = j.size() - 3; k < j.size(); ++k)
    if (!(j[k] <= 0.15 * j[k - 1] + 1e-11 * scale)) os << "jump " << j[k] << " after " << j[k - 1] << "; ";
  if (!(j.back() <= 1e-6 * scale)) os << "last jump " << j.back() << " not small vs scale " << scale << "; ";
  *why = os.str();
  return why->empty();
}

void expectVanishingJumps(const std::vector<double> &j, const std::vector<double> &t, double scale,
                          const std::string &what) {
  std::string why;
  EXPECT_TRUE(jumpsVanish(j, t, scale, &why)) << what << ": " << why;
}

// The 3x3 path F(d) = U diag(s1, s2, -s2 + d) V^T (2x2: diag(s1, -s1 + d); 3x2: diag(s1, d)): alpha increases
// monotonically with d; d* where alpha = target is found by bisection on the kernel's alpha.
template <int R, int C>
struct SingularPath {
  Mat<R, R> U;
  Mat<C, C> V;
  double s1, s2;
  Mat<R, C> operator()(double d) const {
    return U.template leftCols<C>() * nearSingularSigma<R, C>(s1, s2, d).asDiagonal() * V.transpose();
  }
  double crossing(double alphaTarget) const {
    double lo = 0.0, hi = (R == 3 && C == 3) ? s2 : 0.5 * s1;
    for (int it = 0; it < 200; ++it) {
      const double mid = 0.5 * (lo + hi);
      (rootValue((*this)(mid)).alpha < alphaTarget ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  }
};

template <int R, int C>
SingularPath<R, C> makePath(Rng &rng, double scale) {
  return {randomRotation<R>(rng), randomRotation<C>(rng), scale * rng.uniform(1.0, 1.4), scale * rng.uniform(0.5, 0.8)};
}

template <int R, int C>
void mollifierContinuity() {
  Rng rng(seedOf(std::string("mollifier C1 ") + shapeTag<R, C>()));
  for (double proxy : {0.0, 0.37}) {
    MollifierParams p;
    p.proxy = proxy;
    const auto path = makePath<R, C>(rng, bandScale<R, C>());
    const Vec<C> a = randomUnit<C>(rng);
    auto fn = [&](const Mat<R, C> &F, Order o) { return mollifiedI4<R, C>(F, a, p, o); };
    for (double boundary : {p.eps, 3.0 * p.eps}) {
      const double dStar = path.crossing(boundary);
      const double scaleV = std::abs(invariantI4<R, C>(path(dStar), a).value) + 1.0;
      const double scaleG = invariantI4<R, C>(path(dStar), a).grad.norm();
      // Steps relative to the distance to the singular set (d*), so the path stays on one side of alpha = 0.
      const auto js = jumps<R, C>(fn, path, dStar, 1e-2 * dStar, 6);
      const std::string what = std::string(shapeTag<R, C>()) + " mollified I4, proxy " + std::to_string(proxy) +
                               ", across alpha = " + std::to_string(boundary);
      expectVanishingJumps(js.value, js.t, scaleV, what + " (value)");
      expectVanishingJumps(js.grad, js.t, scaleG, what + " (PK1)");
      recordError(std::string("mollifier C1 last value jump ") + shapeTag<R, C>(), js.value.back() / scaleV);
      recordError(std::string("mollifier C1 last PK1 jump   ") + shapeTag<R, C>(), js.grad.back() / scaleG);
      // And the blend really switches here: at d* - 0.1 d* / d* + 0.1 d* one side is the proxy / the raw value.
      if (boundary == p.eps) {
        EXPECT_EQ(fn(path(0.9 * dStar), Order::Value).value, proxy * fiberTensor<C>(a).trace());
        EXPECT_NE(fn(path(1.1 * dStar), Order::Value).value, proxy * fiberTensor<C>(a).trace());
      } else {
        const Mat<R, C> Fa = path(1.1 * dStar);
        EXPECT_EQ(fn(Fa, Order::Value).value, (invariantI4<R, C>(Fa, a, Order::Value).value));
        const Mat<R, C> Fb = path(0.9 * dStar);
        EXPECT_NE(fn(Fb, Order::Value).value, (invariantI4<R, C>(Fb, a, Order::Value).value));
      }
    }
  }
}

TEST(Mollifier, C1AcrossEpsAnd3Eps_3x3) { mollifierContinuity<3, 3>(); }
TEST(Mollifier, C1AcrossEpsAnd3Eps_2x2) { mollifierContinuity<2, 2>(); }
TEST(Mollifier, C1AcrossEpsAnd3Eps_3x2) { mollifierContinuity<3, 2>(); }

// ---- aberration barrier -----------------------------------------------------------------------------------------------

TEST(Barrier, ProfileVanishesToSecondOrderAtEps) {
  const double eps = BarrierParams{}.eps;
  ASSERT_EQ(eps, 1e-2);
  const BarrierProfile at = barrierProfile(eps, eps);
  EXPECT_EQ(at.value, 0.0);
  EXPECT_EQ(at.d1, 0.0);
  EXPECT_EQ(at.d2, 0.0);
  for (double alpha : {eps * (1 + 1e-12), 2 * eps, 1.0, 1e10}) {
    const BarrierProfile b = barrierProfile(alpha, eps);
    EXPECT_EQ(b.value + std::abs(b.d1) + std::abs(b.d2), 0.0) << alpha;
  }
  // Just below eps: b ~ t^3/eps, b' ~ -3 t^2/eps, b'' ~ 6 t/eps (t = eps - alpha), i.e. C2 at eps.
  for (double t : {1e-4, 1e-6, 1e-8}) {
    const BarrierProfile b = barrierProfile(eps - t, eps);
    EXPECT_NEAR(b.value / (t * t * t / eps), 1.0, 0.05) << t;
    EXPECT_NEAR(b.d1 / (-3.0 * t * t / eps), 1.0, 0.05) << t;
    EXPECT_NEAR(b.d2 / (6.0 * t / eps), 1.0, 0.05) << t;
  }
}

TEST(Barrier, ProfileDerivativesMatchFiniteDifferences) {
  const double eps = 1e-2;
  for (double alpha : {1e-6, 1e-4, 1e-3, 5e-3, 9.9e-3}) {
    const double h = 1e-4 * std::min(alpha, eps - alpha);  // b ~ (eps - alpha)^3 near eps
    const BarrierProfile b = barrierProfile(alpha, eps), p = barrierProfile(alpha + h, eps),
                         m = barrierProfile(alpha - h, eps);
    EXPECT_LT(relErr((p.value - m.value) / (2 * h), b.d1), 1e-6) << alpha;
    EXPECT_LT(relErr((p.d1 - m.d1) / (2 * h), b.d2), 1e-6) << alpha;
    EXPECT_GT(b.value, 0.0);
    EXPECT_LT(b.d1, 0.0);  // repulsive: energy decreases as alpha grows
  }
}

TEST(Barrier, BlowsUpAtZeroAndIsInfiniteAtOrBelowZero) {
  const double eps = 1e-2;
  double last = 0.0;
  for (double alpha : {1e-3, 1e-6, 1e-12, 1e-50, 1e-300}) {
    const double b = barrierProfile(alpha, eps).value;
    EXPECT_GT(b, last) << alpha;  // monotone increase towards 0
    EXPECT_GE(b, 0.99 * eps * eps * std::log(eps / alpha) * std::pow(1 - alpha / eps, 2)) << alpha;
    last = b;
  }
  EXPECT_GT(last, 0.06);  // eps^2 ln(eps / 1e-300) = 0.0686: unbounded like a log
  for (double alpha : {0.0, -0.0, -1e-12, -1.0, std::numeric_limits<double>::quiet_NaN()})
    EXPECT_EQ(barrierProfile(alpha, eps).value, std::numeric_limits<double>::infinity()) << alpha;
  // At an exactly singular F the element barrier is +inf (alpha = 0): F = -I (3x3, triple root), a 2x2 reflection
  // (f = 0) and a collapsed cloth triangle.
  EXPECT_EQ((aberrationBarrier<3, 3>(-Mat<3, 3>::Identity()).value), std::numeric_limits<double>::infinity());
  Mat<2, 2> refl;
  refl << 1, 0, 0, -1;
  EXPECT_EQ((aberrationBarrier<2, 2>(refl).value), std::numeric_limits<double>::infinity());
  Mat<3, 2> collapsed;
  collapsed << 1, 2, 0, 0, 0, 0;
  EXPECT_EQ((aberrationBarrier<3, 2>(collapsed).value), std::numeric_limits<double>::infinity());
}

template <int R, int C>
void barrierFd() {
  Rng rng(seedOf(std::string("barrier fd ") + shapeTag<R, C>()));
  int active = 0;
  for (double alpha : {1e-3, 2e-3, 5e-3, 9e-3, 2e-2}) {
    const Mat<R, C> F = alphaF<R, C>(rng, alpha, false);
    const bool inside = alpha < 1e-2;
    FdExpect ex;
    ex.allowZeroGradient = ex.allowZeroHessian = !inside;
    const auto rep = expectDerivatives<R, C>(
        [](const Mat<R, C> &G, Order o) { return aberrationBarrier<R, C>(G, BarrierParams{}, o); }, F,
        std::string("barrier ") + shapeTag<R, C>() + " alpha=" + std::to_string(alpha),
        std::string("barrier ") + shapeTag<R, C>() + (inside ? " active" : " inactive"), ex);
    if (inside) {
      EXPECT_GT(rep.analytic.value, 0.0);
      ++active;
    } else {
      EXPECT_EQ(rep.analytic.value + rep.gradNorm + rep.hessNorm, 0.0);
    }
  }
  EXPECT_EQ(active, 4);
}

TEST(Barrier, FiniteDifferencesInsideActiveRegion_3x3) { barrierFd<3, 3>(); }
TEST(Barrier, FiniteDifferencesInsideActiveRegion_2x2) { barrierFd<2, 2>(); }
TEST(Barrier, FiniteDifferencesInsideActiveRegion_3x2) { barrierFd<3, 2>(); }

// C2 across alpha = eps along a path: value, PK1 and Hessian jumps all vanish.
template <int R, int C>
void barrierContinuity() {
  Rng rng(seedOf(std::string("barrier C2 ") + shapeTag<R, C>()));
  const auto path = makePath<R, C>(rng, 1.0);
  const double dStar = path.crossing(1e-2);
  auto fn = [](const Mat<R, C> &F, Order o) { return aberrationBarrier<R, C>(F, BarrierParams{}, o); };
  const auto js = jumps<R, C>(fn, path, dStar, 1e-2 * dStar, 6);
  // Scales: the barrier's derivatives a little inside the active region.
  const auto inside = fn(path(0.5 * dStar), Order::Hessian);
  ASSERT_GT(inside.hess.norm(), 0.0);
  const std::string what = std::string(shapeTag<R, C>()) + " barrier across alpha = eps";
  expectVanishingJumps(js.value, js.t, std::abs(inside.value), what + " (value)");
  expectVanishingJumps(js.grad, js.t, inside.grad.norm(), what + " (PK1)");
  expectVanishingJumps(js.hess, js.t, inside.hess.norm(), what + " (Hessian)");
}

TEST(Barrier, C2AcrossEps_3x3) { barrierContinuity<3, 3>(); }
TEST(Barrier, C2AcrossEps_2x2) { barrierContinuity<2, 2>(); }
TEST(Barrier, C2AcrossEps_3x2) { barrierContinuity<3, 2>(); }

// ---- kim_aa's discontinuity (the baseline's known flaw) -----------------------------------------------------------

// F(s) = Q S(s) V^T with the symmetric stretch S(s) = [[s, g], [g, 1]] (+ 1 on the diagonal for tets) in the frame V
// of the material basis: R = Q V^T is the polar rotation all along (S's eigenvalues have pairwise sums > 0), so
// I4(u1) = s changes sign at s = 0 while I5(u1) = |S e1|^2 = s^2 + g^2 stays ~ g^2 > 0. With the per-direction
// coefficient 2 mu, the term is mu (sqrt(I5) - sign(I4))^2, and the energy jumps by
//   mu [(r + 1)^2 - (r - 1)^2] = 4 mu r,   r = sqrt(I5) = g.
template <int D>
void kimJump() {
  constexpr ElementShape shape = D == 3 ? ElementShape::Tet : ElementShape::Planar;
  Rng rng(seedOf("kim jump " + std::to_string(D)));
  const double g = 0.3;
  const Mat<D, D> Q = randomRotation<D>(rng), V = randomRotation<D>(rng);
  auto path = [&](double s) {
    Mat<D, D> S = Mat<D, D>::Identity();
    S(0, 0) = s;
    S(0, 1) = S(1, 0) = g;
    return Mat<D, D>(Q * S * V.transpose());
  };
  Material kim;
  kim.kind = EnergyKind::KimAA;
  kim.mu = 1.7;
  kim.lambda = 2.9;
  kim.basis = Eigen::Matrix3d::Identity();
  kim.basis.topLeftCorner<D, D>() = V.transpose();  // rows u_k = V e_k
  ASSERT_EQ(energies::finalizeMaterial(kim, shape), "");
  Material iarap = kim;
  iarap.kind = EnergyKind::Iarap;
  iarap.singularity.mode = SingularityMode::Mollifier;
  ASSERT_EQ(energies::finalizeMaterial(iarap, shape), "");
  const CellData<D> cell;
  const Vec<D> u1 = V.col(0);
  const double expected = 4.0 * kim.mu * g;
  // The continuity detector used for the mollifier and the barrier flags this path (non-vacuity of those tests).
  {
    auto energy = [&](const Mat<D, D> &F, Order o) { return energies::evaluateEnergy<D, D>(kim, cell, F, o); };
    auto line = [&](double s) { return path(s); };
    const auto js = jumps<D, D>(energy, line, 0.0, 1e-3, 6);
    std::string why;
    EXPECT_FALSE(jumpsVanish(js.value, js.t, energy(path(0.01), Order::Value).value, &why));
    EXPECT_NEAR(js.value.back() / expected, 1.0, 1e-6);
  }
  for (double t : {1e-3, 1e-6, 1e-9}) {
    // I4(u1) really changes sign across s = 0 (closed form, as kim_aa reads it) while I5 stays ~ g^2.
    EXPECT_NEAR((invariantI4<D, D>(path(t), u1, Order::Value).value), t, 1e-12);
    EXPECT_NEAR((invariantI4<D, D>(path(-t), u1, Order::Value).value), -t, 1e-12);
    const double ek = energies::evaluateEnergy<D, D>(kim, cell, path(-t), Order::Value).value -
                      energies::evaluateEnergy<D, D>(kim, cell, path(t), Order::Value).value;
    const double ei = energies::evaluateEnergy<D, D>(iarap, cell, path(-t), Order::Value).value -
                      energies::evaluateEnergy<D, D>(iarap, cell, path(t), Order::Value).value;
    // The jump does not vanish as t -> 0: it converges to 4 mu sqrt(I5) (continuous parts change by O(t)).
    EXPECT_NEAR(ek / expected, 1.0, 20.0 * t) << "t=" << t;
    // The paper's energy is continuous on the same path.
    EXPECT_LT(std::abs(ei), 20.0 * t * kim.mu) << "t=" << t;
    recordError("kim_aa jump / (4 mu sqrt(I5)) - 1, " + std::to_string(D) + "D t=" + sci(t), std::abs(ek / expected - 1));
  }
}

TEST(KimAA, JumpsByFourMuSqrtI5WhereI4ChangesSign_Tet) { kimJump<3>(); }
TEST(KimAA, JumpsByFourMuSqrtI5WhereI4ChangesSign_Planar) { kimJump<2>(); }

// ---- PSD projection -----------------------------------------------------------------------------------------------------

// Indefinite symmetric matrix with known spectrum: Q diag(lam) Q^T, Q random orthogonal, about half the eigenvalues
// negative, magnitudes over six decades.
template <int N>
Mat<N, N> knownSpectrum(Rng &rng, Mat<N, N> *Q, Vec<N> *lam) {
  const Eigen::HouseholderQR<Mat<N, N>> qr(rng.gaussMat<N, N>());
  *Q = qr.householderQ();
  for (int i = 0; i < N; ++i) (*lam)[i] = (i % 2 ? -1.0 : 1.0) * std::pow(10.0, rng.uniform(-3.0, 3.0));
  return *Q * lam->asDiagonal() * Q->transpose();
}

template <int N>
void psdProjection() {
  Rng rng(seedOf("psd " + std::to_string(N)));
  for (int trial = 0; trial < 20; ++trial) {
    Mat<N, N> Q;
    Vec<N> lam;
    const Mat<N, N> H = knownSpectrum<N>(rng, &Q, &lam);
    const Mat<N, N> P = projectToPSD<N>(H);
    const double scale = H.norm();
    EXPECT_GE(symmetricEigenvalues<N>(P).minCoeff(), -1e-12 * scale) << "trial " << trial;
    EXPECT_LT((P - P.transpose()).norm(), 1e-14 * scale);
    // Nearest PSD matrix: the negative eigenvalues clamped to 0, the positive eigenpairs kept.
    const Mat<N, N> expected = Q * lam.cwiseMax(0.0).asDiagonal() * Q.transpose();
    EXPECT_LT((P - expected).norm(), 1e-12 * scale) << "trial " << trial;
    // Idempotent.
    EXPECT_LT((projectToPSD<N>(P) - P).norm(), 1e-12 * scale);
    recordError("PSD projection vs clamped spectrum N=" + std::to_string(N), (P - expected).norm() / scale);

    // Already PSD (including a singular one): returned unchanged up to round-off.
    const Mat<N, N> B = rng.gaussMat<N, N>();
    Mat<N, N> S = B * B.transpose();
    EXPECT_LT((projectToPSD<N>(S) - S).norm(), 1e-15 * S.norm());
    const Vec<N> v = rng.gaussMat<N, 1>();
    S = v * v.transpose();  // rank 1: eigenvalues 0 (to round-off) and |v|^2
    EXPECT_LT((projectToPSD<N>(S) - S).norm(), 1e-13 * S.norm());
  }
}

// Absolute-value filtering (Chen et al. 2024): the negative eigenvalues flipped, the eigenvectors kept; None returns
// the symmetric part; both Clamp and Abs leave a positive definite matrix unchanged.
template <int N>
void eigenFilters() {
  Rng rng(seedOf("eigen filters " + std::to_string(N)));
  for (int trial = 0; trial < 20; ++trial) {
    Mat<N, N> Q;
    Vec<N> lam;
    const Mat<N, N> H = knownSpectrum<N>(rng, &Q, &lam);
    const double scale = H.norm();
    const Mat<N, N> absH = filterEigenvalues<N>(H, EigenFilter::Abs);
    const Mat<N, N> expected = Q * lam.cwiseAbs().asDiagonal() * Q.transpose();
    EXPECT_LT((absH - expected).norm(), 1e-12 * scale) << "trial " << trial;
    recordError("abs eigenvalue filter vs |spectrum| N=" + std::to_string(N), (absH - expected).norm() / scale);
    // abs - clamp = the flipped negative part, PSD; abs(H) is at least as stiff as clamp(H) in every direction.
    EXPECT_GE(symmetricEigenvalues<N>(absH - filterEigenvalues<N>(H, EigenFilter::Clamp)).minCoeff(), -1e-12 * scale);
    Mat<N, N> nonsym = H, sym = H;
    nonsym(0, N - 1) += 1.0;
    sym(0, N - 1) += 0.5;
    sym(N - 1, 0) += 0.5;
    EXPECT_LT((filterEigenvalues<N>(nonsym, EigenFilter::None) - sym).norm(), 1e-14 * scale);
    const Mat<N, N> B = rng.gaussMat<N, N>();
    const Mat<N, N> S = B * B.transpose() + Mat<N, N>::Identity();
    EXPECT_LT((filterEigenvalues<N>(S, EigenFilter::Abs) - S).norm(), 1e-15 * S.norm());
    EXPECT_LT((filterEigenvalues<N>(S, EigenFilter::Clamp) - S).norm(), 1e-15 * S.norm());
  }
}

TEST(EigenFilter, AbsFlipsNegativeEigenvalues_4) { eigenFilters<4>(); }
TEST(EigenFilter, AbsFlipsNegativeEigenvalues_6) { eigenFilters<6>(); }
TEST(EigenFilter, AbsFlipsNegativeEigenvalues_9) { eigenFilters<9>(); }

TEST(PsdProjection, ClampsNegativeEigenvaluesKeepsPsdInput_4) { psdProjection<4>(); }
TEST(PsdProjection, ClampsNegativeEigenvaluesKeepsPsdInput_6) { psdProjection<6>(); }
TEST(PsdProjection, ClampsNegativeEigenvaluesKeepsPsdInput_9) { psdProjection<9>(); }

// The energies' Hessians are indefinite at inverted / compressed F; their projections are PSD.
TEST(PsdProjection, ProjectedEnergyHessiansArePsd) {
  int indefinite = 0;
  for (const EnergyCase &ec : allEnergyCases()) {
    withShape(ec.shape, [&](auto Rc, auto Cc) {
      constexpr int R = decltype(Rc)::value, C = decltype(Cc)::value;
      constexpr int N = R * C;
      Rng rng(seedOf("psd energy " + caseName(ec)));
      const auto setup = makeMaterial<R, C>(ec.kind, ec.mode, rng);
      for (const auto &s : standardFamilies<R, C>(seedOf("psd F " + caseName(ec)))) {
        const Mat<N, N> H = energies::evaluateEnergy<R, C>(setup.m, setup.cell, s.F).hess;
        const Mat<N, N> P = projectToPSD<N>(H);
        indefinite += symmetricEigenvalues<N>(H).minCoeff() < 0.0;
        EXPECT_GE(symmetricEigenvalues<N>(P).minCoeff(), -1e-12 * H.norm()) << caseName(ec) << " " << s.label;
      }
    });
  }
  EXPECT_GT(indefinite, 50);  // the projection actually had work to do
}

}  // namespace
}  // namespace aries::test
