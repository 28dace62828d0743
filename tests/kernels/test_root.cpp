// Partial derivatives of the root function f up to third order (paper Table 3, Eqs. 107-139), checked
// against finite differences taken directly in the space of the root invariants y:
//   3x3: y = (I_C, II_C, J), f = largest real root of p(t) = t^4 - 2 I_C t^2 - 8 J t - I_C^2 + 2 II_C
//   2x2: y = (I_C, J),       f = sqrt(I_C + 2 J)
//   3x2: y = (I_C, III_C),   f = sqrt(I_C + 2 sqrt(III_C))
// The reference is independent of the kernel code: f(y) is computed in long double at perturbed invariant values
// (monotone Newton on p from above for 3x3, the closed forms for 2x2 / 3x2), and the reference f_l(y), f_lm(y) come
// from generic implicit differentiation of q(f(y), y) = 0 for a polynomial q:
//   f_l  = -q_l / q_t,
//   f_lm = -(q_lm + q_tl f_m + q_tm f_l + q_tt f_l f_m) / q_t.
// Checked: kernel f_l vs central FD of f, kernel f_lm vs FD of f_l, kernel f_lmn vs FD of f_lm (h = 1e-4 .. 1e-8
// relative to |y_l|, best relative error < 1e-6), with the derivatives scaled by |y_l| per index so that all
// components weigh alike in the norm.
#include "kernels/root_function.hpp"
#include "kernels/svd_polar.hpp"
#include "test_support.hpp"

namespace aries::test {
namespace {

using namespace aries::kernels;
using LD = long double;

template <int K>
using VecL = Eigen::Matrix<LD, K, 1>;
template <int K>
using MatL = Eigen::Matrix<LD, K, K>;

// ---- the defining polynomial q(t, y) of each shape and its partial derivatives ------------------------------------
template <int K>
struct QPartials {
  LD q, qt, qtt;
  VecL<K> qy, qty;
  MatL<K> qyy;
};

template <int R, int C>
struct RootPoly;

template <>
struct RootPoly<3, 3> {
  static constexpr int K = 3;
  static QPartials<3> at(LD t, const VecL<3> &y) {
    const LD I = y[0], II = y[1], J = y[2];
    QPartials<3> d;
    d.q = t * t * t * t - 2 * I * t * t - 8 * J * t - I * I + 2 * II;
    d.qt = 4 * t * t * t - 4 * I * t - 8 * J;
    d.qtt = 12 * t * t - 4 * I;
    d.qy << -2 * t * t - 2 * I, 2, -8 * t;
    d.qty << -4 * t, 0, -8;
    d.qyy.setZero();
    d.qyy(0, 0) = -2;
    return d;
  }
  // Largest real root: monotone Newton from above (p is convex and increasing right of its largest root).
  static LD root(const VecL<3> &y) {
    LD t = 2.0L * std::sqrt(3.0L * y[0]) + 1.0L;
    LD last = std::numeric_limits<LD>::infinity();
    for (int it = 0; it < 400; ++it) {
      const QPartials<3> d = at(t, y);
      const LD step = d.q / d.qt;
      if (!(step > 0) || !(step < last)) break;
      t -= step;
      last = step;
    }
    return t;
  }
};

template <>
struct RootPoly<2, 2> {  // q = t^2 - I_C - 2J
  static constexpr int K = 2;
  static QPartials<2> at(LD t, const VecL<2> &y) {
    QPartials<2> d;
    d.q = t * t - y[0] - 2 * y[1];
    d.qt = 2 * t;
    d.qtt = 2;
    d.qy << -1, -2;
    d.qty << 0, 0;
    d.qyy.setZero();
    return d;
  }
  static LD root(const VecL<2> &y) { return std::sqrt(y[0] + 2 * y[1]); }
};

template <>
struct RootPoly<3, 2> {  // q = (t^2 - I_C)^2 - 4 III_C  (root with t^2 - I_C = 2 sqrt(III_C) >= 0)
  static constexpr int K = 2;
  static QPartials<2> at(LD t, const VecL<2> &y) {
    const LD I = y[0], III = y[1], w = t * t - I;
    QPartials<2> d;
    d.q = w * w - 4 * III;
    d.qt = 4 * t * w;
    d.qtt = 12 * t * t - 4 * I;
    d.qy << -2 * w, -4;
    d.qty << -4 * t, 0;
    d.qyy.setZero();
    d.qyy(0, 0) = 2;
    return d;
  }
  static LD root(const VecL<2> &y) { return std::sqrt(y[0] + 2 * std::sqrt(y[1])); }
};

// Independent f, f_l, f_lm at y (long double).
template <int R, int C>
struct IndependentRoot {
  static constexpr int K = RootPoly<R, C>::K;
  LD f;
  VecL<K> d1;
  MatL<K> d2;
  explicit IndependentRoot(const VecL<K> &y) {
    f = RootPoly<R, C>::root(y);
    const QPartials<K> q = RootPoly<R, C>::at(f, y);
    d1 = -q.qy / q.qt;
    for (int l = 0; l < K; ++l)
      for (int m = 0; m < K; ++m)
        d2(l, m) = -(q.qyy(l, m) + q.qty[l] * d1[m] + q.qty[m] * d1[l] + q.qtt * d1[l] * d1[m]) / q.qt;
  }
};

// Root invariants of a (double) F evaluated in long double, so the reference sees exactly the kernel's point.
template <int R, int C>
VecL<RootPoly<R, C>::K> rootInvariantsLD(const Mat<R, C> &F) {
  const Eigen::Matrix<LD, R, C> G = F.template cast<LD>();
  const Eigen::Matrix<LD, C, C> Cg = G.transpose() * G;
  VecL<RootPoly<R, C>::K> y;
  if constexpr (R == 3 && C == 3)
    y << G.squaredNorm(), Cg.squaredNorm(), G.determinant();
  else if constexpr (R == 2)
    y << G.squaredNorm(), G.determinant();
  else
    y << G.squaredNorm(), Cg.determinant();
  return y;
}

template <int R, int C>
double svdAlpha(const Mat<R, C> &F) {
  return alphaFromSigma<R, C>(signedSvd(F).s);
}

// Test points: generic, inverted, stretched, and near alpha = 0 (normalized alpha 0.1 = Newton path, 0.03 = Horn
// eigen path of the 3x3 root, threshold 0.05). Near alpha = 0 the point is at distance ~alpha^2 from the fold of
// f(y) (a double root of p), so FD in y is truncation limited there: at alpha_n = 0.03 the best error (h = 1e-8) is
// ~1e-7 for f_lmn, still decreasing like h^2, i.e. the reference, not the kernel, sets that number.
template <int R, int C>
std::vector<Sample<R, C>> rootSamples() {
  Rng rng(seedOf(std::string("root ") + shapeTag<R, C>()));
  std::vector<Sample<R, C>> out;
  Vec<C> s;
  if constexpr (C == 3) {
    s << 1.3, 0.9, 0.6;
    out.push_back({"random", "sigma=(1.3,0.9,0.6)", fromSigma<R, C>(s, rng)});
    s << 1.2, 0.8, -0.5;
    out.push_back({"inverted", "sigma=(1.2,0.8,-0.5)", fromSigma<R, C>(s, rng)});
    s << 3.0, 1.0, 0.2;
    out.push_back({"stretched", "sigma=(3,1,0.2)", fromSigma<R, C>(s, rng)});
  } else {
    s << 1.3, 0.7;
    out.push_back({"random", "sigma=(1.3,0.7)", fromSigma<R, C>(s, rng)});
    if constexpr (R == 2) {
      s << 1.2, -0.5;
      out.push_back({"inverted", "sigma=(1.2,-0.5)", fromSigma<R, C>(s, rng)});
    }
    s << 3.0, 0.2;
    out.push_back({"stretched", "sigma=(3,0.2)", fromSigma<R, C>(s, rng)});
  }
  out.push_back({"random", "random Gaussian", randomF<R, C>(rng)});
  out.push_back({"near_singular", "alpha_n=0.1", alphaF<R, C>(rng, 0.1, true)});
  out.push_back({"near_singular", "alpha_n=0.03", alphaF<R, C>(rng, 0.03, true)});
  return out;
}

// Best (over h) scaled relative error of FD of g(y) along each y_n against the analytic tensor `an(n)` (a K-vector
// or KxK matrix per direction n). `scale` holds |y_l|: g must return its entries already multiplied by the scales of
// their own indices, an(n) the analytic derivative multiplied by the scales of all its indices (including n); the FD
// quotient along n is multiplied by scale[n] here.
template <int K, class G, class Analytic>
double bestFdError(const VecL<K> &y, const VecL<K> &scale, G &&g, Analytic &&an) {
  double best = std::numeric_limits<double>::infinity();
  for (double h : kFdSteps) {
    double num = 0.0, den = 0.0;
    for (int n = 0; n < K; ++n) {
      VecL<K> yp = y, ym = y;
      const LD dy = static_cast<LD>(h) * scale[n];
      yp[n] += dy;
      ym[n] -= dy;
      const auto fd = ((g(yp) - g(ym)) / (2 * dy)).eval();
      const auto ref = an(n);  // analytic derivative along n (already scaled by the other indices' scales)
      const auto diff = (fd.template cast<double>() * static_cast<double>(scale[n]) - ref).eval();
      num += diff.squaredNorm();
      den += ref.squaredNorm();
    }
    best = std::min(best, std::sqrt(num) / std::max(std::sqrt(den), kTiny));
  }
  return best;
}

template <int R, int C>
void checkRootDerivatives() {
  constexpr int K = RootPoly<R, C>::K;
  for (const auto &s : rootSamples<R, C>()) {
    const std::string what = std::string(shapeTag<R, C>()) + " " + s.label + "\n  " + describe<R, C>(s.F);
    const RootDerivatives<K> rd = rootDerivatives(s.F, 3);
    const VecL<K> y = rootInvariantsLD<R, C>(s.F);
    const VecL<K> sc = y.cwiseAbs();
    const IndependentRoot<R, C> ind(y);
    const Vec<K> scD = sc.template cast<double>();

    if constexpr (R == 3 && C == 3) {  // both evaluation paths of the 3x3 root are covered
      const bool eigenExpected = normalizeAlpha<R, C>(svdAlpha<R, C>(s.F), s.F) < kRootEigenThreshold;
      EXPECT_EQ(rd.root.fromEigen, eigenExpected) << what;
    }
    // The independent reference itself: its f is the sum of signed singular values of F.
    const SignedSvd<R, C> svd = signedSvd(s.F);
    EXPECT_LT(relErr(static_cast<double>(ind.f), svd.s.sum()), 1e-13) << "independent root solver: " << what;
    // Kernel f and first derivatives at the point agree with the independent ones.
    EXPECT_LT(relErr(rd.root.f, static_cast<double>(ind.f)), 1e-13) << "f: " << what;
    EXPECT_LT(relErr(Vec<K>(rd.d1.cwiseProduct(scD)), Vec<K>(ind.d1.template cast<double>().cwiseProduct(scD))),
              1e-11)
        << "f_l at the point: " << what;

    // f_l vs FD of f.
    const double e1 = bestFdError<K>(
        y, sc, [](const VecL<K> &yy) { return Eigen::Matrix<LD, 1, 1>(IndependentRoot<R, C>(yy).f); },
        [&](int n) { return Eigen::Matrix<double, 1, 1>(rd.d1[n] * scD[n]); });
    // f_lm vs FD of f_l (FD along m gives column m; entries scaled by |y_l| |y_m|).
    const double e2 = bestFdError<K>(
        y, sc, [&](const VecL<K> &yy) { return VecL<K>(IndependentRoot<R, C>(yy).d1.cwiseProduct(sc)); },
        [&](int m) { return Vec<K>(rd.d2.col(m).cwiseProduct(scD) * scD[m]); });
    // f_lmn vs FD of f_lm (FD along n gives the slice d3[n]).
    const double e3 = bestFdError<K>(
        y, sc, [&](const VecL<K> &yy) { return MatL<K>(sc.asDiagonal() * IndependentRoot<R, C>(yy).d2 * sc.asDiagonal()); },
        [&](int n) { return Mat<K, K>(scD.asDiagonal() * rd.d3[n] * scD.asDiagonal() * scD[n]); });
    EXPECT_LT(e1, kFdTol) << "f_l vs FD of f: " << what;
    EXPECT_LT(e2, kFdTol) << "f_lm vs FD of f_l: " << what;
    EXPECT_LT(e3, kFdTol) << "f_lmn vs FD of f_lm: " << what;
    // Non-vacuous: the derivative tensors are nonzero and the third-order tensor is fully symmetric.
    EXPECT_GT(rd.d2.norm(), 0.0);
    double d3norm = 0.0, d3asym = 0.0;
    for (int l = 0; l < K; ++l)
      for (int m = 0; m < K; ++m)
        for (int n = 0; n < K; ++n) {
          d3norm += rd.d3[n](l, m) * rd.d3[n](l, m);
          d3asym = std::max({d3asym, std::abs(rd.d3[n](l, m) - rd.d3[l](n, m)), std::abs(rd.d3[n](l, m) - rd.d3[m](l, n))});
        }
    EXPECT_GT(d3norm, 0.0);
    EXPECT_EQ(d3asym, 0.0) << "f_lmn not symmetric: " << what;
    const std::string key = std::string(shapeTag<R, C>()) + " " + s.family;
    recordError("root f_l   vs FD " + key, e1);
    recordError("root f_lm  vs FD " + key, e2);
    recordError("root f_lmn vs FD " + key, e3);
  }
}

TEST(RootDerivatives, UpToThirdOrder_3x3) { checkRootDerivatives<3, 3>(); }
TEST(RootDerivatives, UpToThirdOrder_2x2) { checkRootDerivatives<2, 2>(); }
TEST(RootDerivatives, UpToThirdOrder_3x2) { checkRootDerivatives<3, 2>(); }

// The `upTo` argument only limits work: lower orders are identical whatever is requested.
TEST(RootDerivatives, UpToLimitsWorkOnly) {
  Rng rng(11);
  const Mat<3, 3> F = randomF<3, 3>(rng);
  const auto r1 = rootDerivatives(F, 1), r2 = rootDerivatives(F, 2), r3 = rootDerivatives(F, 3);
  EXPECT_EQ(r1.d1, r3.d1);
  EXPECT_EQ(r2.d2, r3.d2);
  EXPECT_EQ(r1.d2.norm(), 0.0);
  EXPECT_GT(r3.d3[0].norm(), 0.0);
}

// The FD-in-invariant-space comparison is sharp: a single wrong third-order entry (1e-4 relative) is detected.
TEST(RootDerivatives, CheckerDetectsWrongThirdDerivative) {
  Rng rng(12);
  const Mat<3, 3> F = randomF<3, 3>(rng);
  RootDerivatives<3> rd = rootDerivatives(F, 3);
  const VecL<3> y = rootInvariantsLD<3, 3>(F), sc = y.cwiseAbs();
  const Vec<3> scD = sc.cast<double>();
  auto err = [&]() {
    return bestFdError<3>(
        y, sc, [&](const VecL<3> &yy) { return MatL<3>(sc.asDiagonal() * IndependentRoot<3, 3>(yy).d2 * sc.asDiagonal()); },
        [&](int n) { return Mat<3, 3>(scD.asDiagonal() * rd.d3[n] * scD.asDiagonal() * scD[n]); });
  };
  EXPECT_LT(err(), kFdTol);
  rd.d3[1](2, 2) *= 1.0 + 1e-3;  // f_2JJ slightly wrong
  EXPECT_GT(err(), 1e-5);
}

}  // namespace
}  // namespace aries::test
