// Shared helpers of the kernel test suite (aries-kernel-tests):
//  * a deterministic random source (fixed seeds: every run tests the same matrices),
//  * random rotations, unit fibers and orthonormal fiber pairs,
//  * F families built from signed singular values: random (identity + Gaussian), inverted (det < 0), strongly
//    stretched/compressed, and near the singular set alpha = 0 with a prescribed (absolute or normalized) alpha,
//  * ONE finite-difference checker (finiteDifferences / expectDerivatives) for any callable Psi(F, order) ->
//    Derivs<R*C>, used for every invariant and every energy: PK1 against central differences of the value, Hessian
//    against central differences of the PK1, best relative error over h = 1e-4 ... 1e-8 (2- and 4-point stencils),
//  * energy cases: every (kind, shape, singularity mode) the library supports, with a finalized generic material,
//  * an error ledger that prints the worst error observed per family at the end of the run.
#pragma once

#include "energies/energy.hpp"
#include "kernels/svd_polar.hpp"
#include "kernels/types.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace aries::test {

using kernels::Derivs;
using kernels::Mat;
using kernels::Order;
using kernels::Vec;

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kFdTol = 1e-6;                                   // FD acceptance: best relative error over the steps below
constexpr double kFdSteps[] = {1e-4, 1e-5, 1e-6, 1e-7, 1e-8};     // central-difference step sizes

// Deterministic seed from a name (FNV-1a), so each test gets its own but reproducible matrices.
inline std::uint64_t seedOf(const std::string &name) {
  std::uint64_t h = 1469598103934665603ULL;
  for (unsigned char c : name) h = (h ^ c) * 1099511628211ULL;
  return h;
}

// ------------------------------------------------------------------------------------------------------------------
// Random source
// ------------------------------------------------------------------------------------------------------------------
// std::mt19937_64 is fully specified by the standard, but std::normal_distribution / uniform_real_distribution are
// not (libstdc++ and libc++ differ), so the distributions are written out here: the same matrices on every platform.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : gen_(seed) {}
  double unit() { return static_cast<double>(gen_() >> 11) * 0x1.0p-53; }  // [0, 1)
  double uniform(double lo, double hi) { return lo + (hi - lo) * unit(); }
  double gauss() {  // Box-Muller
    if (haveSpare_) {
      haveSpare_ = false;
      return spare_;
    }
    const double u = 1.0 - unit(), v = unit();  // u in (0, 1]
    const double r = std::sqrt(-2.0 * std::log(u)), t = 2.0 * 3.141592653589793 * v;
    spare_ = r * std::sin(t);
    haveSpare_ = true;
    return r * std::cos(t);
  }
  template <int R, int C>
  Mat<R, C> gaussMat() {
    Mat<R, C> M;
    for (int i = 0; i < R; ++i)
      for (int j = 0; j < C; ++j) M(i, j) = gauss();
    return M;
  }

 private:
  std::mt19937_64 gen_;
  double spare_ = 0.0;
  bool haveSpare_ = false;
};

// "3x3", "2x2" or "3x2": the element shape in test messages.
template <int R, int C>
constexpr const char *shapeTag() {
  return (R == 3 && C == 3) ? "3x3" : (R == 2 ? "2x2" : "3x2");
}

template <int C>
inline Vec<C> randomUnit(Rng &rng) {
  Vec<C> v;
  do {
    for (int i = 0; i < C; ++i) v[i] = rng.gauss();
  } while (v.norm() < 1e-3);
  return v.normalized();
}

// Uniformly distributed rotation (det = +1).
template <int D>
inline Mat<D, D> randomRotation(Rng &rng) {
  if constexpr (D == 3) {
    Eigen::Vector4d q;
    do {
      for (int i = 0; i < 4; ++i) q[i] = rng.gauss();
    } while (q.norm() < 1e-3);
    q.normalize();
    return Eigen::Quaterniond(q[0], q[1], q[2], q[3]).toRotationMatrix();
  } else {
    const double t = rng.uniform(-3.141592653589793, 3.141592653589793);
    Mat<2, 2> Q;
    Q << std::cos(t), -std::sin(t), std::sin(t), std::cos(t);
    return Q;
  }
}

// A random unit vector b orthogonal to the unit vector a.
template <int C>
inline Vec<C> randomOrthogonalUnit(const Vec<C> &a, Rng &rng) {
  Vec<C> b;
  do {
    b = randomUnit<C>(rng);
    b -= a.dot(b) * a;
  } while (b.norm() < 1e-2);
  return b.normalized();
}

// ------------------------------------------------------------------------------------------------------------------
// F from signed singular values, and alpha computed from them (independently of the kernels)
// ------------------------------------------------------------------------------------------------------------------

// F = U diag(s) V^T with random U, V. Square F: U, V rotations, so a negative entry of s makes det F < 0 (the
// signed convention: only the smallest-magnitude singular value should carry a sign). 3x2 F: the first two columns of
// a random 3x3 rotation, V a random 2x2 rotation (s >= 0 by convention).
template <int R, int C>
inline Mat<R, C> fromSigma(const Vec<C> &s, Rng &rng) {
  const Mat<R, R> U = randomRotation<R>(rng);
  const Mat<C, C> V = randomRotation<C>(rng);
  return U.template leftCols<C>() * s.asDiagonal() * V.transpose();
}

// alpha from signed singular values (Eqs. 28-30): 8(s1+s2)(s1+s3)(s2+s3), s1+s2, and for 3x2
// alpha = f sqrt(III_C) = (s1+s2) s1 s2. NOTE: the paper's Eq. 30 writes the last one as "(s1+s2) sqrt(s1 s2)",
// which contradicts its own first form (III_C = det C = (s1 s2)^2, so sqrt(III_C) = s1 s2) and its derivatives
// (Eqs. 149-150 differentiate f sqrt(III_C)); the kernel implements f sqrt(III_C), which is what is tested.
template <int R, int C>
inline double alphaFromSigma(const Vec<C> &s) {
  if constexpr (R == 3 && C == 3)
    return 8.0 * (s[0] + s[1]) * (s[0] + s[2]) * (s[1] + s[2]);
  else if constexpr (R == 2)
    return s[0] + s[1];
  else
    return (s[0] + s[1]) * s[0] * s[1];
}

// Degree of homogeneity of alpha in F (3, 1, 3): alpha_n = alpha / |F|^degree is scale free.
template <int R, int C>
constexpr int alphaDegree() {
  return (R == 3 && C == 3) ? 3 : (R == 2 ? 1 : 3);
}
template <int R, int C>
inline double normalizeAlpha(double alpha, const Mat<R, C> &F) {
  return alpha / std::pow(F.norm(), alphaDegree<R, C>());
}

// Singular values with one free parameter delta that drives alpha to 0 as delta -> 0+:
//   3x3 (s1, s2, -s2 + delta)   2x2 (s1, -s1 + delta)   3x2 (s1, delta)
template <int R, int C>
inline Vec<C> nearSingularSigma(double s1, double s2, double delta) {
  Vec<C> s;
  if constexpr (R == 3 && C == 3)
    s << s1, s2, -s2 + delta;
  else if constexpr (R == 2)
    s << s1, -s1 + delta;
  else
    s << s1, delta;
  return s;
}

// Solve for delta so that alpha (absolute, or normalized when `normalized`) equals `target`, by bisection on the
// singular-value formula (monotone in delta on the bracket used).
template <int R, int C>
inline Vec<C> sigmaWithAlpha(double s1, double s2, double target, bool normalized) {
  auto alphaOf = [&](double d) {
    const Vec<C> s = nearSingularSigma<R, C>(s1, s2, d);
    const double a = alphaFromSigma<R, C>(s);
    return normalized ? a / std::pow(s.norm(), alphaDegree<R, C>()) : a;
  };
  double lo = 0.0, hi = (R == 3 && C == 3) ? s2 : 0.5 * s1;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (alphaOf(mid) < target ? lo : hi) = mid;
  }
  return nearSingularSigma<R, C>(s1, s2, 0.5 * (lo + hi));
}

// ------------------------------------------------------------------------------------------------------------------
// F families
// ------------------------------------------------------------------------------------------------------------------
template <int R, int C>
struct Sample {
  std::string family;  // "random", "inverted", "stretched", "near_singular", ...
  std::string label;   // family plus details, for failure messages
  Mat<R, C> F;
};

// Identity (or [I; 0] for cloth) plus Gaussian noise of size `sigma`, accepted when alpha_n > minAlphaN and, for square
// F, det F > 0 (the inverted family is separate).
template <int R, int C>
inline Mat<R, C> randomF(Rng &rng, double sigma = 0.3, double minAlphaN = 0.2) {
  for (;;) {
    const Mat<R, C> F = Mat<R, C>::Identity() + sigma * rng.gaussMat<R, C>();
    if constexpr (R == C) {
      if (F.determinant() <= 0.0) continue;
    }
    if (normalizeAlpha<R, C>(alphaFromSigma<R, C>(kernels::signedSvd(F).s), F) > minAlphaN) return F;
  }
}

// det F < 0 with the sign on the smallest singular value and alpha comfortably > 0 (square F only).
template <int R, int C>
inline Mat<R, C> invertedF(Rng &rng) {
  static_assert(R == C, "inverted F needs a square F");
  Vec<C> s;
  if constexpr (C == 3)
    s << rng.uniform(1.0, 1.6), rng.uniform(0.6, 0.95), -rng.uniform(0.1, 0.45);
  else
    s << rng.uniform(1.0, 1.6), -rng.uniform(0.1, 0.6);
  return fromSigma<R, C>(s, rng);
}

// Strongly stretched / compressed: sigma = (3, 1, 0.2) (2D / cloth: (3, 0.2)), randomly rotated; `compress` gives
// (0.3, 0.25, 0.2)-like all-compressed states instead.
template <int R, int C>
inline Mat<R, C> stretchedF(Rng &rng, bool compress = false) {
  Vec<C> s;
  if constexpr (C == 3) {
    if (compress)
      s << 0.35, 0.25, 0.2;
    else
      s << 3.0, 1.0, 0.2;
  } else {
    if (compress)
      s << 0.3, 0.2;
    else
      s << 3.0, 0.2;
  }
  return fromSigma<R, C>(s, rng);
}

// F with alpha (absolute or normalized) equal to `target`, in the near-singular pattern above, randomly rotated.
// `scale` shrinks the singular values (s1 ~ 1.2 scale, s2 ~ 0.65 scale): alpha is an absolute quantity (eps = 1e-3
// of the mollifier, 1e-2 of the barrier), so a smaller element reaches the same alpha at a larger normalized alpha.
template <int R, int C>
inline Mat<R, C> alphaF(Rng &rng, double target, bool normalized, double scale = 1.0) {
  const double s1 = scale * rng.uniform(1.0, 1.4), s2 = scale * rng.uniform(0.5, 0.8);
  return fromSigma<R, C>(sigmaWithAlpha<R, C>(s1, s2, target, normalized), rng);
}

// The standard FD families: 2 random, 2 inverted (square F), stretched, compressed, and near-singular F with
// normalized alpha 0.1 (Newton path of the 3x3 root) and 0.04 (Horn eigen path, threshold 0.05) -- small enough for
// large derivatives (the I4 Hessian grows like 1/alpha^3), large enough for a central difference with h >= 1e-8 to
// resolve them.
template <int R, int C>
inline std::vector<Sample<R, C>> standardFamilies(std::uint64_t seed) {
  Rng rng(seed);
  std::vector<Sample<R, C>> out;
  for (int k = 0; k < 2; ++k) out.push_back({"random", "random #" + std::to_string(k), randomF<R, C>(rng)});
  if constexpr (R == C)
    for (int k = 0; k < 2; ++k) out.push_back({"inverted", "inverted #" + std::to_string(k), invertedF<R, C>(rng)});
  out.push_back({"stretched", "stretched sigma=(3,1,0.2)", stretchedF<R, C>(rng)});
  out.push_back({"stretched", "compressed sigma=(0.35,0.25,0.2)", stretchedF<R, C>(rng, true)});
  out.push_back({"near_singular", "near singular alpha_n=0.1", alphaF<R, C>(rng, 0.1, true)});
  out.push_back({"near_singular", "near singular alpha_n=0.04", alphaF<R, C>(rng, 0.04, true)});
  return out;
}

inline std::string sci(double x) {
  std::ostringstream os;
  os << std::scientific;
  os.precision(0);
  os << x;
  return os.str();
}

template <int R, int C>
inline std::string describe(const Mat<R, C> &F) {
  std::ostringstream os;
  os.precision(17);
  os << "F (row-major) = [";
  for (int i = 0; i < R; ++i)
    for (int j = 0; j < C; ++j) os << (i || j ? ", " : "") << F(i, j);
  os << "]";
  return os.str();
}

// ------------------------------------------------------------------------------------------------------------------
// Error ledger: worst error per family, printed after all tests (the numbers quoted in reports)
// ------------------------------------------------------------------------------------------------------------------
class ErrorLedger {
 public:
  static ErrorLedger &instance() {
    static ErrorLedger l;
    return l;
  }
  void record(const std::string &key, double err) {
    if (!std::isfinite(err)) err = std::numeric_limits<double>::infinity();
    double &w = worst_[key];
    w = std::max(w, err);
  }
  const std::map<std::string, double> &worst() const { return worst_; }

 private:
  std::map<std::string, double> worst_;
};
inline void recordError(const std::string &key, double err) { ErrorLedger::instance().record(key, err); }

// ------------------------------------------------------------------------------------------------------------------
// Relative errors
// ------------------------------------------------------------------------------------------------------------------
constexpr double kTiny = 1e-300;

template <class A, class B>
inline double relErr(const A &got, const B &ref) {
  return (got - ref).norm() / std::max(ref.norm(), kTiny);
}
inline double relErr(double got, double ref) { return std::abs(got - ref) / std::max(std::abs(ref), kTiny); }

// ------------------------------------------------------------------------------------------------------------------
// The finite-difference checker
// ------------------------------------------------------------------------------------------------------------------
template <int N>
struct FdReport {
  double gradErr = std::numeric_limits<double>::infinity();  // best over h of |fd - an| / max(|an|, tiny)
  double hessErr = std::numeric_limits<double>::infinity();
  double gradStep = 0.0, hessStep = 0.0;                     // h that achieved it
  double gradNorm = 0.0, hessNorm = 0.0;                     // |analytic|
  double hessAsymmetry = 0.0;                                // |H - H^T| / |H|
  double orderMismatch = 0.0;  // value / gradient differences between Order::Value, Gradient and Hessian calls
  Derivs<N> analytic;
};

// The function a derivative check differentiates: fn(F, order) -> Derivs<R*C>. Type-erased, so that the checker is
// compiled once per shape (R, C) and translation unit, not once per test's lambda (inlined and optimized around each
// kernel call: when the kernel tests were built at -O2, test_invariants.cpp alone took 115 s to compile, 78 s with
// this). NonDeduced: R and C come from the
// call's explicit template arguments, never from the lambda.
template <int R, int C>
using DerivativeFn = std::function<Derivs<R * C>(const Mat<R, C> &, Order)>;
template <class T>
struct NonDeduced {
  using type = T;
};

// fn(F, order) -> Derivs<R*C>. PK1 is checked against central differences of fn(., Order::Value).value, the Hessian
// against central differences of fn(., Order::Gradient).grad (so the reduced-order code paths are exercised too).
// For every step h in kFdSteps two central differences are formed, the classic 2-point one
//   (g(F + h E) - g(F - h E)) / 2h                                                   (error O(h^2) + noise / h)
// and the 4-point one (-g(F + 2hE) + 8 g(F + hE) - 8 g(F - hE) + g(F - 2hE)) / 12h  (error O(h^4) + noise / h);
// each gives one relative error for the whole gradient (whole Hessian) and the best over h and stencil is reported.
// The 4-point stencil matters near alpha = 0: there the closed-form PK1 carries round-off noise of ~10 eps / alpha_n^3
// relative (the chain of Eq. 19 sums terms ~1/alpha^3 that cancel), which swamps the 2-point difference at the small
// h its h^2 truncation error needs; a derivative that is wrong by more than ~1e-6 fails either way.
template <int R, int C>
FdReport<R * C> finiteDifferences(const typename NonDeduced<DerivativeFn<R, C>>::type &fn, const Mat<R, C> &F) {
  constexpr int N = R * C;
  FdReport<N> rep;
  rep.analytic = fn(F, Order::Hessian);
  const Derivs<N> &an = rep.analytic;
  rep.gradNorm = an.grad.norm();
  rep.hessNorm = an.hess.norm();
  rep.hessAsymmetry = (an.hess - an.hess.transpose()).norm() / std::max(rep.hessNorm, kTiny);
  {
    const Derivs<N> v = fn(F, Order::Value), g = fn(F, Order::Gradient);
    const double sv = std::max(std::abs(an.value), kTiny);
    rep.orderMismatch = std::max({std::abs(v.value - an.value) / sv, std::abs(g.value - an.value) / sv,
                                  (g.grad - an.grad).norm() / std::max(rep.gradNorm, kTiny)});
    if (std::isnan(rep.orderMismatch)) rep.orderMismatch = std::numeric_limits<double>::infinity();
  }
  for (double h : kFdSteps) {
    Vec<N> fdGrad2, fdGrad4;
    Mat<N, N> fdHess2, fdHess4;
    for (int k = 0; k < N; ++k) {
      Vec<N> e = Vec<N>::Zero();
      e[k] = h;
      const Mat<R, C> E = kernels::unflatten<R, C>(e);
      const Derivs<N> p1 = fn(F + E, Order::Gradient), m1 = fn(F - E, Order::Gradient);
      const Derivs<N> p2 = fn(F + 2.0 * E, Order::Gradient), m2 = fn(F - 2.0 * E, Order::Gradient);
      fdGrad2[k] = (p1.value - m1.value) / (2.0 * h);
      fdHess2.col(k) = (p1.grad - m1.grad) / (2.0 * h);
      fdGrad4[k] = (-p2.value + 8.0 * p1.value - 8.0 * m1.value + m2.value) / (12.0 * h);
      fdHess4.col(k) = (-p2.grad + 8.0 * p1.grad - 8.0 * m1.grad + m2.grad) / (12.0 * h);
    }
    for (const double eg : {(fdGrad2 - an.grad).norm() / std::max(rep.gradNorm, kTiny),
                            (fdGrad4 - an.grad).norm() / std::max(rep.gradNorm, kTiny)})
      if (eg < rep.gradErr) rep.gradErr = eg, rep.gradStep = h;  // NaN/inf at one h never wins
    for (const double eh : {(fdHess2 - an.hess).norm() / std::max(rep.hessNorm, kTiny),
                            (fdHess4 - an.hess).norm() / std::max(rep.hessNorm, kTiny)})
      if (eh < rep.hessErr) rep.hessErr = eh, rep.hessStep = h;
  }
  return rep;
}

struct FdExpect {
  bool allowZeroGradient = false;  // the analytic PK1 may be exactly zero (e.g. the mollifier's flat proxy region)
  bool allowZeroHessian = false;   // the analytic Hessian may be exactly zero (linear invariants, proxy region)
  double tol = kFdTol;
};

// Runs finiteDifferences and asserts: finite value, PK1 and Hessian each within `tol` of FD, Hessian symmetric,
// reduced-order evaluations consistent, and (unless allowed) a nonzero analytic PK1 / Hessian so the comparison
// is not vacuous. `ledgerKey` collects the worst errors per family.
template <int R, int C>
FdReport<R * C> expectDerivatives(const typename NonDeduced<DerivativeFn<R, C>>::type &fn, const Mat<R, C> &F,
                                  const std::string &what, const std::string &ledgerKey, FdExpect ex = {}) {
  const FdReport<R * C> rep = finiteDifferences<R, C>(fn, F);
  const std::string ctx = what + "\n  " + describe<R, C>(F);
  EXPECT_TRUE(std::isfinite(rep.analytic.value)) << ctx;
  EXPECT_TRUE(rep.analytic.grad.allFinite() && rep.analytic.hess.allFinite()) << ctx;
  if (!ex.allowZeroGradient) {
    EXPECT_GT(rep.gradNorm, 0.0) << "vacuous PK1 check (analytic PK1 is zero): " << ctx;
  }
  if (!ex.allowZeroHessian) {
    EXPECT_GT(rep.hessNorm, 0.0) << "vacuous Hessian check (analytic Hessian is zero): " << ctx;
  }
  EXPECT_LT(rep.gradErr, ex.tol) << "PK1 vs FD (best h = " << rep.gradStep << "), |PK1| = " << rep.gradNorm << ": "
                                 << ctx;
  EXPECT_LT(rep.hessErr, ex.tol) << "Hessian vs FD (best h = " << rep.hessStep << "), |H| = " << rep.hessNorm << ": "
                                 << ctx;
  // Symmetry up to round-off: near alpha = 0 the Hessian is a sum of large cancelling terms (G S G^T of Eq. 19),
  // whose evaluation is not bit-symmetric (observed up to ~4e-8 relative for the barrier at alpha_n ~ 3e-4); a
  // structural asymmetry would be O(1) (and is also caught column by column by the FD comparison).
  EXPECT_LT(rep.hessAsymmetry, 1e-6) << "Hessian not symmetric: " << ctx;
  recordError("Hessian asymmetry " + ledgerKey, rep.hessAsymmetry);
  EXPECT_LT(rep.orderMismatch, 1e-13) << "Order::Value / Gradient / Hessian evaluations disagree: " << ctx;
  if (rep.gradNorm > 0.0) recordError("FD PK1    " + ledgerKey, rep.gradErr);
  if (rep.hessNorm > 0.0) recordError("FD Hessian " + ledgerKey, rep.hessErr);
  return rep;
}

// ------------------------------------------------------------------------------------------------------------------
// Energies: every (kind, shape, singularity mode) the library supports, and a finalized material for it
// ------------------------------------------------------------------------------------------------------------------
using energies::CellData;
using energies::ElementShape;
using energies::EnergyKind;
using energies::Material;
using energies::SingularityMode;

// Every energy of the registry (energies/energy_list.hpp): a new energy is in every test that loops over these.
#define ARIES_TEST_KIND(Name) EnergyKind::Name,
inline constexpr EnergyKind kAllKinds[] = {ARIES_ENERGIES(ARIES_TEST_KIND)};
#undef ARIES_TEST_KIND
inline constexpr ElementShape kAllShapes[] = {ElementShape::Tet, ElementShape::Planar, ElementShape::Cloth};
inline constexpr SingularityMode kAllModes[] = {SingularityMode::None, SingularityMode::Mollifier,
                                                SingularityMode::Barrier};

struct EnergyCase {
  EnergyKind kind;
  ElementShape shape;
  SingularityMode mode;
};

inline const char *shapeTag(ElementShape s) {
  return s == ElementShape::Tet ? "tet" : s == ElementShape::Planar ? "planar" : "cloth";
}
inline std::string caseName(const EnergyCase &c) {
  return std::string(energies::energyName(c.kind)) + "_" + shapeTag(c.shape) + "_" +
         energies::singularityName(c.mode);
}
inline std::ostream &operator<<(std::ostream &os, const EnergyCase &c) { return os << caseName(c); }

// Every supported (kind, shape) pair; energies with I4/I6 terms in all three singularity modes, the others in the
// only mode they have (none).
inline std::vector<EnergyCase> allEnergyCases() {
  std::vector<EnergyCase> out;
  for (EnergyKind k : kAllKinds)
    for (ElementShape s : kAllShapes) {
      if (!energies::energySupportsShape(k, s)) continue;
      if (energies::energyContainsStretchInvariant(k))
        for (SingularityMode m : kAllModes) out.push_back({k, s, m});
      else
        out.push_back({k, s, SingularityMode::None});
    }
  return out;
}

template <int C>
struct MaterialSetup {
  Material m;
  CellData<C> cell;
};

// An orthonormal material basis (rows) with the in-plane directions first for 2D elements.
inline Eigen::Matrix3d randomBasis(Rng &rng, bool planar) {
  if (!planar) return randomRotation<3>(rng).transpose();
  const Mat<2, 2> Q = randomRotation<2>(rng);
  Eigen::Matrix3d B = Eigen::Matrix3d::Identity();
  B.topLeftCorner<2, 2>() = Q.transpose();
  return B;
}

// A finalized material of the given kind with generic parameters (all coefficients distinct and O(1), so that
// swapped or dropped terms change the numbers) and random per-element data.
template <int R, int C>
inline MaterialSetup<C> makeMaterial(EnergyKind kind, SingularityMode mode, Rng &rng) {
  constexpr ElementShape shape = (R == 3 && C == 3) ? ElementShape::Tet : (R == 2 ? ElementShape::Planar
                                                                                  : ElementShape::Cloth);
  const bool planar = (C == 2);
  MaterialSetup<C> s;
  Material &m = s.m;
  m.kind = kind;
  m.mu = 1.7;
  m.lambda = 2.9;
  m.mu1 = 2.1;
  m.mu2 = 1.3;
  m.gamma = 2.3;
  m.beta = 0.8;
  m.basis = randomBasis(rng, planar);
  m.basisCoeffs = Eigen::Vector3d(0.7, 1.9, 1.2);
  m.numDirections = 4;
  for (int k = 0; k < m.numDirections; ++k) {
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    d.head<C>() = randomUnit<C>(rng);
    m.directions[k] = d;
    m.directionCoeffs[k] = 0.3 + 0.5 * k;
  }
  m.singularity.mode = mode;
  s.cell.a = randomUnit<C>(rng);
  s.cell.b = (kind == EnergyKind::Bw461) ? randomOrthogonalUnit<C>(s.cell.a, rng) : randomUnit<C>(rng);
  const Mat<C, C> Q = randomRotation<C>(rng);
  Vec<C> lam;
  for (int i = 0; i < C; ++i) lam[i] = 0.6 + 0.4 * i;
  s.cell.target = Q * lam.asDiagonal() * Q.transpose();
  s.cell.curvature = 0.6;
  const std::string err = energies::finalizeMaterial(m, shape);
  EXPECT_EQ(err, "") << energies::energyName(kind);
  return s;
}

template <int R, int C>
inline auto energyFn(const MaterialSetup<C> &s) {
  return [&s](const Mat<R, C> &F, Order o) { return energies::evaluateEnergy<R, C>(s.m, s.cell, F, o); };
}

// Dispatch a callable templated on <R, C> by element shape.
template <class Fn>
inline void withShape(ElementShape shape, Fn &&fn) {
  if (shape == ElementShape::Tet) fn(std::integral_constant<int, 3>{}, std::integral_constant<int, 3>{});
  if (shape == ElementShape::Planar) fn(std::integral_constant<int, 2>{}, std::integral_constant<int, 2>{});
  if (shape == ElementShape::Cloth) fn(std::integral_constant<int, 3>{}, std::integral_constant<int, 2>{});
}

}  // namespace aries::test
