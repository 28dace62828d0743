// Closed-form eigensystem of the F-space Hessian of an isotropic energy Psi(I1, I2, I3) of a 3x3 F, and the
// eigenvalue filters of psd_projection.hpp applied through it (no 9x9 eigensolve).
//
// Smith, de Goes and Kim 2019, "Analytic Eigensystems for Isotropic Distortion Energies" (Sec. 5, 7): with the
// invariants I1 = tr S = f (the root function), I2 = |F|^2 = I_C, I3 = det F = J and F = U Sigma V^T, the Hessian
// d2Psi/dF2 = sum_a Psi_a d2I_a/dF2 + sum_ab Psi_ab dI_a/dF (x) dI_b/dF has nine eigenvectors U M V^T:
//   twist (i,j), M = (e_i e_j^T - e_j e_i^T)/sqrt2:  lambda = 2 Psi_2 + 2 Psi_1 / (s_i + s_j) + Psi_3 s_k
//   flip  (i,j), M = (e_i e_j^T + e_j e_i^T)/sqrt2:  lambda = 2 Psi_2 - Psi_3 s_k
//   scaling,     M = diag(w):                         w an eigenvector of A = d2Psi(s)/ds2 (3x3), lambda its eigenvalue
// (k the third index; s the signed singular values, sum s = f). The SVD is not needed: F = R S with the analytic
// rotation R (rotation.hpp) and the right stretch S = R^T F = V Sigma V^T, so U M V^T = R (V M V^T) and only the
// eigenvectors V of the symmetric 3x3 S are required (a 3x3 Jacobi eigensolve, accurate and orthonormal also for
// repeated stretches, where any basis of the repeated eigenspace gives valid modes: the flip and the scaling
// eigenvalue coincide there).
//
// The filtered Hessian is sum_m phi(lambda_m) q_m q_m^T (phi = 0 for negative lambda when clamping, |lambda| for
// absolute-value filtering).
#pragma once

#include "kernels/psd_projection.hpp"
#include "kernels/types.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

namespace aries::kernels {

// Symmetric 3x3 eigendecomposition by cyclic Jacobi rotations (Numerical Recipes' rotation, written out for 3x3:
// Eigen's generic JacobiRotation / SelfAdjointEigenSolver cost 2-3x more here): eigenvalues to ~eps |A| and
// eigenvectors orthonormal to eps also where eigenvalues repeat (the trigonometric closed form loses ~sqrt(eps)
// there). A = V diag(lam) V^T. Converges quadratically; 3-5 sweeps.
inline void symmetricEigen3(const Mat<3, 3> &A, Vec<3> &lam, Mat<3, 3> &V) {
  double a[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) a[i][j] = 0.5 * (A(i, j) + A(j, i));
  V.setIdentity();
  constexpr int kPairs[3][3] = {{0, 1, 2}, {0, 2, 1}, {1, 2, 0}};  // (p, q, r): rotate in (p, q), r the third index
  for (int sweep = 0; sweep < 12; ++sweep) {
    const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    const double diag = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
    if (!(off > 1e-34 * diag)) break;  // off-diagonal below ~eps |A| / 20 (and 0 / NaN guards)
    for (const auto &pqr : kPairs) {
      const int p = pqr[0], q = pqr[1], r = pqr[2];
      const double apq = a[p][q];
      // A rotation that cannot change the diagonal in floating point (NR's test): the entry is round-off.
      if (std::abs(apq) <= 1e-18 * (std::abs(a[p][p]) + std::abs(a[q][q]))) {
        a[p][q] = a[q][p] = 0.0;
        continue;
      }
      const double theta = (a[q][q] - a[p][p]) / (2.0 * apq);
      const double t = std::abs(theta) > 1e150 ? 0.5 / theta
                                                : std::copysign(1.0, theta) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
      const double c = 1.0 / std::sqrt(t * t + 1.0), sn = t * c;
      a[p][p] -= t * apq;
      a[q][q] += t * apq;
      a[p][q] = a[q][p] = 0.0;
      const double arp = a[r][p], arq = a[r][q];
      a[r][p] = a[p][r] = c * arp - sn * arq;
      a[r][q] = a[q][r] = sn * arp + c * arq;
      for (int k = 0; k < 3; ++k) {
        const double vkp = V(k, p), vkq = V(k, q);
        V(k, p) = c * vkp - sn * vkq;
        V(k, q) = sn * vkp + c * vkq;
      }
    }
  }
  lam << a[0][0], a[1][1], a[2][2];
}

// Eigen's direct solver (trigonometric eigenvalues, eigenvectors from cross products: ~140 ns against ~330 ns for the
// Jacobi sweeps) where the eigenvalues are well separated, so its eigenvectors are accurate (error ~ eps / relative
// gap <= 1e-12 here); the Jacobi sweeps above where two eigenvalues are within 1e-4 of each other (relative).
template <int Rows, int Cols, IfShape<Rows, Cols, 3, 3> = 0>
inline void symmetricEigen3Fast(const Mat<Rows, Cols> &A, Vec<3> &lam, Mat<3, 3> &V) {
  const Mat<3, 3> As = 0.5 * (A + A.transpose());
  Eigen::SelfAdjointEigenSolver<Mat<3, 3>> direct;
  direct.computeDirect(As);
  const Vec<3> &l = direct.eigenvalues();  // ascending
  const double scale = std::max(std::abs(l[0]), std::abs(l[2]));
  if (!(l[1] - l[0] > 1e-4 * scale && l[2] - l[1] > 1e-4 * scale) || !direct.eigenvectors().allFinite()) {
    symmetricEigen3(As, lam, V);
    return;
  }
  lam = l;
  V = direct.eigenvectors();
}

// First and second derivatives of an isotropic Psi w.r.t. (I1, I2, I3) = (f, I_C, J).
struct IsotropicPsiDerivatives {
  Vec<3> first = Vec<3>::Zero();
  Mat<3, 3> second = Mat<3, 3>::Zero();
};

// The nine eigenvalues and F-space eigenvectors (columns, unit length, row-major flattening) of the Hessian of Psi
// at F = R S. Order: twists (1,2), (2,0), (0,1); flips in the same order; the three scaling modes.
struct IsotropicEigensystem {
  Vec<9> lambda;
  Mat<9, 9> modes;
};

// The twist and flip eigenvalues (pairs (1,2), (2,0), (0,1)) from the signed singular values s (eigenvalues of S).
inline Vec<6> twistFlipEigenvalues(const Vec<3> &s, const IsotropicPsiDerivatives &psi) {
  Vec<6> lam;
  for (int k = 0; k < 3; ++k) {
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    lam[k] = 2.0 * psi.first[1] + 2.0 * psi.first[0] / (s[i] + s[j]) + psi.first[2] * s[k];  // twist (i,j)
    lam[3 + k] = 2.0 * psi.first[1] - psi.first[2] * s[k];                                    // flip (i,j)
  }
  return lam;
}

// A_ij = d2Psi/ds_i ds_j with I1 = sum s, I2 = sum s^2, I3 = prod s.
inline Mat<3, 3> scalingBlock(const Vec<3> &s, const IsotropicPsiDerivatives &psi) {
  Mat<3, 3> G;  // G(i, a) = dI_a / ds_i
  for (int i = 0; i < 3; ++i) {
    G(i, 0) = 1.0;
    G(i, 1) = 2.0 * s[i];
    G(i, 2) = s[(i + 1) % 3] * s[(i + 2) % 3];
  }
  Mat<3, 3> A = G * psi.second * G.transpose();
  for (int i = 0; i < 3; ++i) {
    A(i, i) += 2.0 * psi.first[1];
    for (int j = i + 1; j < 3; ++j) {
      const double cross = psi.first[2] * s[3 - i - j];  // d2 I3 / ds_i ds_j = s_k
      A(i, j) += cross;
      A(j, i) += cross;
    }
  }
  return A;
}

// The stretch frame at F = R S: the signed stretches s with their eigenvectors V (columns) and, with U = R V, the
// twist and flip modes (columns: twists (1,2), (2,0), (0,1), then the flips) and D = [vec(u_k v_k^T)], in which a
// scaling mode with eigenvector w of the scaling block is D w.
struct IsotropicModes {
  Vec<3> s;
  Mat<3, 3> V;
  Mat<9, 6> twistFlip;
  Mat<9, 3> D;
};

template <int Rows, int Cols, IfShape<Rows, Cols, 3, 3> = 0>
inline IsotropicModes isotropicModes(const Mat<Rows, Cols> &F, const Mat<3, 3> &R) {
  IsotropicModes m;
  symmetricEigen3Fast(Mat<3, 3>(R.transpose() * F), m.s, m.V);
  const Mat<3, 3> U = R * m.V;
  constexpr double invSqrt2 = 0.70710678118654752440;
  for (int k = 0; k < 3; ++k) {
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    const Mat<3, 3> ab = U.col(i) * m.V.col(j).transpose(), ba = U.col(j) * m.V.col(i).transpose();
    m.twistFlip.col(k) = flatten<3, 3>(Mat<3, 3>(invSqrt2 * (ab - ba)));
    m.twistFlip.col(3 + k) = flatten<3, 3>(Mat<3, 3>(invSqrt2 * (ab + ba)));
    m.D.col(k) = flatten<3, 3>(Mat<3, 3>(U.col(k) * m.V.col(k).transpose()));
  }
  return m;
}

// The full eigensystem at F = R S (R the analytic rotation of F).
template <int Rows, int Cols, IfShape<Rows, Cols, 3, 3> = 0>
inline IsotropicEigensystem isotropicEigensystem(const Mat<Rows, Cols> &F, const Mat<3, 3> &R,
                                                 const IsotropicPsiDerivatives &psi) {
  const IsotropicModes m = isotropicModes(F, R);
  Vec<3> scaleLam;
  Mat<3, 3> W;
  symmetricEigen3(scalingBlock(m.s, psi), scaleLam, W);
  IsotropicEigensystem es;
  es.lambda << twistFlipEigenvalues(m.s, psi), scaleLam;
  es.modes << m.twistFlip, m.D * W;
  return es;
}

// The eigenvalue-filtered Hessian sum_m phi(lambda_m) q_m q_m^T (phi: psd_projection.hpp's filters; None gives the
// Hessian itself). Built from the eigensystem rather than by correcting the chain-rule Hessian: near the singular
// set (s_i + s_j -> 0) the chain rule loses accuracy like eps / alpha^2 (the root's derivatives grow like 1/alpha^k
// and cancel), the eigensystem only like eps / alpha (measured at alpha_n = 2.3e-3: 1e-9 against 4e-13 relative to a
// reference built from the exact SVD). Where the scaling block A is positive definite (or nothing is filtered) its
// three modes enter as D A D^T, without its eigendecomposition.
template <int Rows, int Cols, IfShape<Rows, Cols, 3, 3> = 0>
inline Mat<9, 9> filteredIsotropicHessian(const Mat<Rows, Cols> &F, const Mat<3, 3> &R,
                                          const IsotropicPsiDerivatives &psi, EigenFilter filter) {
  const IsotropicModes m = isotropicModes(F, R);
  const Vec<6> phi = filterSpectrum<6>(twistFlipEigenvalues(m.s, psi), filter);
  Mat<3, 3> A = scalingBlock(m.s, psi);
  // Positive definite 3x3 (leading minors), else filter its eigenvalues like the others.
  const double m2 = A(0, 0) * A(1, 1) - A(0, 1) * A(0, 1);
  if (filter != EigenFilter::None && !(A(0, 0) > 0.0 && m2 > 0.0 && A.determinant() > 0.0)) {
    Vec<3> lam;
    Mat<3, 3> W;
    symmetricEigen3(A, lam, W);
    A = W * filterSpectrum<3>(lam, filter).asDiagonal() * W.transpose();
  }
  const Mat<9, 6> Qphi = m.twistFlip * phi.asDiagonal();
  const Mat<9, 3> DA = m.D * A;
  Mat<9, 9> out = Qphi.lazyProduct(m.twistFlip.transpose());
  out.noalias() += DA.lazyProduct(m.D.transpose());
  return 0.5 * (out + out.transpose());
}

}  // namespace aries::kernels
