// The root function f = tr(S) = I1 (sum of signed singular values of F) and its partial derivatives up to third order
// w.r.t. the Cauchy-Green invariants it depends on (paper Sec. 3, Eq. 14, App. A, Table 3, Eqs. 107-139), plus the
// singularity measure alpha (Eqs. 27-30).
//
// Root invariants y and their pairing with the fiber invariants in I4 (Eqs. 17, 21, 26):
//   3x3 (tet):    y = (I_C, II_C, J),  I4 = 2 f_1 IV_C + 4 f_2 V_C + f_J I_8
//   2x2 (planar): y = (I_C, J),        I4 = 2 f_1 IV_C +             f_J I_8
//   3x2 (cloth):  y = (I_C, III_C),    I4 = 2 f_1 IV_C +           2 f_3 VI_C
//
// How the 3x3 root is computed (the numerically delicate part; see docs/kernels.md):
//   p(t) = t^4 - 2 I_C t^2 - 8 J t - I_C^2 + 2 II_C has roots s1+s2+s3, s1-s2-s3, -s1+s2-s3, -s1-s2+s3 and f is the
//   largest. p is exactly the characteristic polynomial of Horn's symmetric 4x4 matrix K(F) (the quaternion form of
//   max_R tr(R^T F)), so f = lambda_max(K(F)).
//   1. Scale F to unit Frobenius norm (f is homogeneous of degree 1, alpha of degree 3).
//   2. Monotone Newton on p from t0 = sqrt(3 I_C) >= f (Cauchy-Schwarz). p is convex and increasing on [f, inf)
//      (the largest root of p'' lies left of f by Rolle), so the iterates decrease monotonically; stop when the step
//      stops shrinking (rounding level), or right after a step d below kRootStepStop t: the convergence is quadratic,
//      so the error left is at most about d^2 p''/(2 p'(f)) <= 16 d^2 / alpha_n (p'' <= 32 at |F| = 1), under 1e-15
//      wherever the result is used (alpha_n >= kRootEigenThreshold); this saves the iteration that only confirmed it.
//      Cheap, and accurate to ~20 eps / alpha_n relative.
//   3. Near a double or triple root (alpha_n = p'(f) < kRootEigenThreshold, e.g. s2 ~ -s3 or F ~ -I) the polynomial
//      form is ill-conditioned (Newton only reaches ~sqrt(eps): 1e-8 at alpha_n = 1e-8, 5e-6 at F = -I) whereas the
//      eigenvalues of a symmetric matrix are perfectly conditioned. There f is taken from a backward-stable symmetric
//      eigensolve of K(F) (error ~ eps |F|), alpha = prod_k (f - lambda_k) >= 0 from the same eigenvalues, and the top
//      eigenvector (a unit quaternion) gives a valid rotation R even where the polar factor is not unique (alpha = 0).
// A resolvent-cubic (Ferrari) closed form is NOT used: it loses 1e-2 relative accuracy at sigma = (1000,1,1).
#pragma once

#include "kernels/cauchy_green_invariants.hpp"
#include "kernels/dense_decompositions.hpp"

#include <array>

namespace aries::kernels {

// Normalized alpha (|F| = 1) below which the 3x3 root is taken from Horn's eigenproblem instead of Newton.
constexpr double kRootEigenThreshold = 0.05;
// A Newton step on p below this share of t ends the iteration (step 2 above).
constexpr double kRootStepStop = 1e-9;

template <int R, int C>
struct RootSpace;
template <>
struct RootSpace<3, 3> {
  static constexpr int K = 3;
};
template <>
struct RootSpace<2, 2> {
  static constexpr int K = 2;
};
template <>
struct RootSpace<3, 2> {
  static constexpr int K = 2;
};

// f and alpha at one F. For 3x3, `fromEigen` records that step 3 above was used and `quaternion` holds the top
// eigenvector of K(F) (then the rotation is built from it).
struct RootValue {
  double f = 0.0;
  double alpha = 0.0;
  bool fromEigen = false;
  Eigen::Vector4d quaternion = Eigen::Vector4d(1, 0, 0, 0);
};

// Horn's matrix: q^T K(F) q = tr(R(q)^T F) for unit quaternions q = (w, x, y, z).
inline Eigen::Matrix4d hornMatrix(const Mat<3, 3> &F) {
  Eigen::Matrix4d K;
  K << F(0, 0) + F(1, 1) + F(2, 2), F(2, 1) - F(1, 2), F(0, 2) - F(2, 0), F(1, 0) - F(0, 1),  //
      F(2, 1) - F(1, 2), F(0, 0) - F(1, 1) - F(2, 2), F(0, 1) + F(1, 0), F(0, 2) + F(2, 0),   //
      F(0, 2) - F(2, 0), F(0, 1) + F(1, 0), -F(0, 0) + F(1, 1) - F(2, 2), F(1, 2) + F(2, 1),  //
      F(1, 0) - F(0, 1), F(0, 2) + F(2, 0), F(1, 2) + F(2, 1), -F(0, 0) - F(1, 1) + F(2, 2);
  return K;
}

inline Mat<3, 3> quaternionToRotation(const Eigen::Vector4d &q) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  Mat<3, 3> R;
  R << w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y),  //
      2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x),   //
      2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z;
  return R;
}

template <int R, int C, IfShape<R, C, 3, 3> = 0>
inline RootValue rootValue(const Mat<R, C> &F) {
  RootValue r;
  const double scale = F.norm();
  if (!(scale > 0.0) || !std::isfinite(scale)) {
    r.f = (scale == 0.0) ? 0.0 : std::numeric_limits<double>::quiet_NaN();
    r.alpha = r.f;
    r.fromEigen = true;
    return r;
  }
  const Mat<3, 3> G = F / scale;
  const double IC = G.squaredNorm();
  const double IIC = (G.transpose() * G).squaredNorm();
  const double J = G.determinant();
  double t = std::sqrt(3.0 * IC);
  double lastStep = std::numeric_limits<double>::infinity();
  bool converged = false;
  for (int it = 0; it < 40; ++it) {
    const double t2 = t * t;
    const double p = ((t2 - 2.0 * IC) * t - 8.0 * J) * t - IC * IC + 2.0 * IIC;
    const double dp = 4.0 * t2 * t - 4.0 * IC * t - 8.0 * J;
    if (!(p > 0.0) || !(dp > 0.0)) {  // at (or numerically past) the root
      converged = true;
      break;
    }
    const double step = p / dp;
    if (!(step < lastStep)) {  // no longer contracting: rounding level reached
      converged = true;
      break;
    }
    t -= step;
    lastStep = step;
    if (step <= kRootStepStop * t) {
      converged = true;
      break;
    }
  }
  const double alphaN = 4.0 * t * t * t - 4.0 * IC * t - 8.0 * J;
  if (converged && alphaN >= kRootEigenThreshold) {
    r.f = t * scale;
    r.alpha = alphaN * scale * scale * scale;
    return r;
  }
  const SymmetricEigen<4> eig = symmetricEigen<4>(hornMatrix(G));
  const Eigen::Vector4d &lam = eig.values;  // ascending
  r.f = lam[3] * scale;
  r.alpha = (lam[3] - lam[0]) * (lam[3] - lam[1]) * (lam[3] - lam[2]) * scale * scale * scale;
  r.fromEigen = true;
  r.quaternion = eig.vectors.col(3);
  return r;
}

// A lower bound of the 3x3 alpha without the root: alpha = 8 (s1 + s2)(s1 + s3)(s2 + s3) (Eqs. 27-28, signed singular
// values) is at least 64 J. Where J > 0 all three are positive and s_i + s_j >= 2 sqrt(s_i s_j) (AM-GM), so alpha >=
// 64 s1 s2 s3, with equality where F is a multiple of a rotation; where J <= 0, alpha >= 0 >= 64 J. A test of alpha
// against a threshold at or below this bound needs no root (fem/terms/elastic_cells.hpp: the safeguard's guard).
inline double alphaLowerBound(const Mat<3, 3> &F) { return 64.0 * F.determinant(); }

// 2x2: f = sqrt(I_C + 2J) = |(F00 + F11, F10 - F01)|, a sum of squares without cancellation; alpha = f (Eq. 29).
template <int R, int C, IfShape<R, C, 2, 2> = 0>
inline RootValue rootValue(const Mat<R, C> &F) {
  RootValue r;
  r.f = std::hypot(F(0, 0) + F(1, 1), F(1, 0) - F(0, 1));
  r.alpha = r.f;
  return r;
}

// 3x2: f = sqrt(I_C + 2 sqrt(III_C)) with sqrt(III_C) = |f0 x f1| = s1 s2; alpha = f sqrt(III_C) (Eq. 30).
template <int R, int C, IfShape<R, C, 3, 2> = 0>
inline RootValue rootValue(const Mat<R, C> &F) {
  RootValue r;
  const Eigen::Vector3d c0 = F.col(0), c1 = F.col(1);
  const double area = c0.cross(c1).norm();
  r.f = std::sqrt(F.squaredNorm() + 2.0 * area);
  r.alpha = r.f * area;
  return r;
}

// Partial derivatives of f w.r.t. its root invariants y: d1[l] = f_l, d2(l,m) = f_lm, d3[n](l,m) = f_lmn.
template <int K>
struct RootDerivatives {
  RootValue root;
  Vec<K> d1 = Vec<K>::Zero();
  Mat<K, K> d2 = Mat<K, K>::Zero();
  std::array<Mat<K, K>, K> d3{};
};

// 3x3, index order (1, 2, J) = (I_C, II_C, J). First order from Lin et al. 2022, second by implicit differentiation
// of p(f(y), y) = 0, third order literally Table 3. `upTo` limits the work (1, 2 or 3).
template <int R, int C, IfShape<R, C, 3, 3> = 0>
inline RootDerivatives<3> rootDerivatives(const Mat<R, C> &F, int upTo) {
  RootDerivatives<3> out;
  out.root = rootValue(F);
  const double f = out.root.f, a = out.root.alpha, IC = F.squaredNorm();
  const double f1 = (2.0 * f * f + 2.0 * IC) / a, f2 = -2.0 / a, fJ = 8.0 * f / a;
  out.d1 << f1, f2, fJ;
  if (upTo < 2) return out;
  const double beta = 12.0 * f * f - 4.0 * IC;  // d alpha / d t
  const double f11 = (2.0 + 8.0 * f * f1 - beta * f1 * f1) / a;
  const double f12 = (4.0 * f * f2 - beta * f1 * f2) / a;
  const double f1J = (4.0 * f * fJ + 8.0 * f1 - beta * f1 * fJ) / a;
  const double f22 = (-beta * f2 * f2) / a;
  const double f2J = (8.0 * f2 - beta * f2 * fJ) / a;
  const double fJJ = (16.0 * fJ - beta * fJ * fJ) / a;
  out.d2 << f11, f12, f1J, f12, f22, f2J, f1J, f2J, fJJ;
  if (upTo < 3) return out;
  // d alpha / d y for y = I_C, II_C, J (the recurring brackets of Table 3).
  const double A1 = 12.0 * f * f * f1 - 4.0 * f - 4.0 * IC * f1;
  const double A2 = 12.0 * f * f * f2 - 4.0 * IC * f2;
  const double AJ = 12.0 * f * f * fJ - 4.0 * IC * fJ - 8.0;
  const double f2sq = f * f;
  const double f111 = (4 * f1 * f1 + 4 * f * f11 - (24 * f * f1 * f1 + 12 * f2sq * f11 - 8 * f1 - 4 * IC * f11) * f1 -
                       2 * A1 * f11) / a;
  const double f112 = (4 * f1 * f2 + 4 * f * f12 - (24 * f * f1 * f2 + 12 * f2sq * f12 - 4 * f2 - 4 * IC * f12) * f1 -
                       A1 * f12 - A2 * f11) / a;
  const double f11J = (4 * fJ * f1 + 4 * f * f1J - (24 * f * f1 * fJ + 12 * f2sq * f1J - 4 * fJ - 4 * IC * f1J) * f1 -
                       A1 * f1J - AJ * f11) / a;
  const double f122 =
      (4 * f2 * f2 + 4 * f * f22 - (24 * f * f2 * f2 + 12 * f2sq * f22 - 4 * IC * f22) * f1 - 2 * A2 * f12) / a;
  const double f12J = (4 * fJ * f2 + 4 * f * f2J - (24 * f * f2 * fJ + 12 * f2sq * f2J - 4 * IC * f2J) * f1 -
                       A2 * f1J - AJ * f12) / a;
  const double f1JJ =
      (4 * fJ * fJ + 4 * f * fJJ - (24 * f * fJ * fJ + 12 * f2sq * fJJ - 4 * IC * fJJ) * f1 - 2 * AJ * f1J) / a;
  const double f222 = (-(24 * f * f2 * f2 + 12 * f2sq * f22 - 4 * IC * f22) * f2 - 2 * A2 * f22) / a;
  const double f22J = (-(24 * f * f2 * fJ + 12 * f2sq * f2J - 4 * IC * f2J) * f2 - A2 * f2J - AJ * f22) / a;
  const double f2JJ = (-(24 * f * fJ * fJ + 12 * f2sq * fJJ - 4 * IC * fJJ) * f2 - 2 * AJ * f2J) / a;
  const double fJJJ = (8 * fJJ - (24 * f * fJ * fJ + 12 * f2sq * fJJ - 4 * IC * fJJ) * fJ - 2 * AJ * fJJ) / a;
  out.d3[0] << f111, f112, f11J, f112, f122, f12J, f11J, f12J, f1JJ;
  out.d3[1] << f112, f122, f12J, f122, f222, f22J, f12J, f22J, f2JJ;
  out.d3[2] << f11J, f12J, f1JJ, f12J, f22J, f2JJ, f1JJ, f2JJ, fJJJ;
  return out;
}

// 2x2, index order (1, J): Eqs. 107-108, 115-117, 133-136.
template <int R, int C, IfShape<R, C, 2, 2> = 0>
inline RootDerivatives<2> rootDerivatives(const Mat<R, C> &F, int upTo) {
  RootDerivatives<2> out;
  out.root = rootValue(F);
  const double f = out.root.f;
  const double f1 = 1.0 / (2.0 * f), fJ = 1.0 / f;
  out.d1 << f1, fJ;
  if (upTo < 2) return out;
  const double f11 = -f1 * f1 / f, f1J = -f1 * fJ / f, fJJ = -fJ * fJ / f;
  out.d2 << f11, f1J, f1J, fJJ;
  if (upTo < 3) return out;
  const double f111 = -3.0 * f1 * f11 / f;
  const double f11J = (-2.0 * f1 * f1J - fJ * f11) / f;
  const double f1JJ = (-2.0 * fJ * f1J - f1 * fJJ) / f;
  const double fJJJ = -3.0 * fJ * fJJ / f;
  out.d3[0] << f111, f11J, f11J, f1JJ;
  out.d3[1] << f11J, f1JJ, f1JJ, fJJJ;
  return out;
}

// 3x2, index order (1, 3) = (I_C, III_C): Eqs. 113-114, 115, 118-119, 133, 137-139.
template <int R, int C, IfShape<R, C, 3, 2> = 0>
inline RootDerivatives<2> rootDerivatives(const Mat<R, C> &F, int upTo) {
  RootDerivatives<2> out;
  out.root = rootValue(F);
  const double f = out.root.f;
  const Eigen::Vector3d c0 = F.col(0), c1 = F.col(1);
  const double s = c0.cross(c1).norm();  // sqrt(III_C)
  const double III = s * s;
  const double f1 = 1.0 / (2.0 * f), f3 = 1.0 / (2.0 * f * s);
  out.d1 << f1, f3;
  if (upTo < 2) return out;
  const double f11 = -f1 * f1 / f, f13 = -f1 * f3 / f;
  const double f33 = (-1.0 / (2.0 * III * s) - 2.0 * f3 * f3) / (2.0 * f);
  out.d2 << f11, f13, f13, f33;
  if (upTo < 3) return out;
  const double f111 = -3.0 * f1 * f11 / f;
  const double f113 = (-2.0 * f1 * f13 - f3 * f11) / f;
  const double f133 = (-2.0 * f3 * f13 - f1 * f33) / f;
  const double f333 = (3.0 / (4.0 * III * III * s) - 6.0 * f3 * f33) / (2.0 * f);
  out.d3[0] << f111, f113, f113, f133;
  out.d3[1] << f113, f133, f133, f333;
  return out;
}

// The root invariants y(F) with their F-derivatives, in the index order used above.
template <int R, int C>
struct RootInvariants {
  static constexpr int K = RootSpace<R, C>::K;
  std::array<Derivs<R * C>, K> y;
};

template <int R, int C, IfShape<R, C, 3, 3> = 0>
inline RootInvariants<3, 3> rootInvariants(const Mat<R, C> &F, Order order) {
  return {{invariantIC<3, 3>(F, order), invariantIIC<3, 3>(F, order), invariantJ(F, order)}};
}
template <int R, int C, IfShape<R, C, 2, 2> = 0>
inline RootInvariants<2, 2> rootInvariants(const Mat<R, C> &F, Order order) {
  return {{invariantIC<2, 2>(F, order), invariantJ(F, order)}};
}
template <int R, int C, IfShape<R, C, 3, 2> = 0>
inline RootInvariants<3, 2> rootInvariants(const Mat<R, C> &F, Order order) {
  return {{invariantIC<3, 2>(F, order), invariantIIIC<3>(F, order)}};
}

// Everything the invariant kernels need about one F, computed once and shared by all terms of an energy: the root
// with its derivatives up to order+1 (I4's Hessian needs third derivatives of f) and the root invariants' derivatives.
template <int R, int C>
struct RootContext {
  static constexpr int K = RootSpace<R, C>::K;
  Mat<R, C> F;
  Order order;
  RootDerivatives<K> rd;
  RootInvariants<R, C> y;
};

template <int R, int C>
inline RootContext<R, C> makeRootContext(const Mat<R, C> &F, Order order = Order::Hessian) {
  return {F, order, rootDerivatives(F, static_cast<int>(order) + 1), rootInvariants(F, order)};
}

}  // namespace aries::kernels
