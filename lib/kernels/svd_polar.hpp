// SVD-based polar decomposition: the reference the closed forms are tested against and the machinery of the
// rotation-variant baselines (arap_svd, SVD-based alx). Not used by the closed-form energies.
//
// Square F (d = 2, 3): signed SVD F = U diag(s) V^T with U, V rotations and the last singular value carrying the
// sign of det F; R = U V^T. Perturbing F = U (diag(s) + E) V^T, the polar rotation is R = U exp(W) V^T with
//   W1_ij = (E_ij - E_ji) / (s_i + s_j)                       (first order: the "twist" modes)
//   W2 s + s W2 = X - X^T,  X = -W1 E + W1^2 diag(s) / 2      (second order)
// which gives dR/dF exactly and the exact Hessian of tr(S D) = tr(R^T F D) without d2R/dF2 in closed form.
// 3x2 F: thin SVD (s >= 0); dR/dF has the in-plane twist 2/(s1+s2) and the out-of-plane modes n v_j^T with 1/s_j.
#pragma once

#include "kernels/dense_decompositions.hpp"
#include "kernels/types.hpp"

namespace aries::kernels {

template <int R, int C>
struct SignedSvd {
  Mat<R, R> U;
  Vec<C> s;
  Mat<C, C> V;
};

template <int D>
inline SignedSvd<D, D> signedSvd(const Mat<D, D> &F) {
  const FullSvd<D, D> svd = fullSvd<D, D>(F);
  SignedSvd<D, D> out{svd.U, svd.s, svd.V};
  if (out.U.determinant() < 0.0) {
    out.U.col(D - 1) *= -1.0;
    out.s[D - 1] *= -1.0;
  }
  if (out.V.determinant() < 0.0) {
    out.V.col(D - 1) *= -1.0;
    out.s[D - 1] *= -1.0;
  }
  return out;
}

template <int R, int C, IfShape<R, C, 3, 2> = 0>
inline SignedSvd<3, 2> signedSvd(const Mat<R, C> &F) {
  const FullSvd<3, 2> svd = fullSvd<3, 2>(F);
  return {svd.U, svd.s, svd.V};
}

template <int D>
inline Mat<D, D> svdRotation(const SignedSvd<D, D> &s) {
  return s.U * s.V.transpose();
}
inline Mat<3, 2> svdRotation(const SignedSvd<3, 2> &s) { return s.U.template leftCols<2>() * s.V.transpose(); }

template <int R, int C>
inline Mat<R, C> svdRotation(const Mat<R, C> &F) {
  return svdRotation(signedSvd(F));
}

// dvec(R)/dvec(F) (row-major flattening), symmetric.
template <int D>
inline Mat<D * D, D * D> svdRotationGradient(const SignedSvd<D, D> &s) {
  Mat<D * D, D * D> G = Mat<D * D, D * D>::Zero();
  for (int i = 0; i < D; ++i)
    for (int j = i + 1; j < D; ++j) {
      const Mat<D, D> Q =
          (s.U.col(i) * s.V.col(j).transpose() - s.U.col(j) * s.V.col(i).transpose()) / std::sqrt(2.0);
      const Vec<D * D> q = flatten<D, D>(Q);
      G += (2.0 / (s.s[i] + s.s[j])) * q * q.transpose();
    }
  return G;
}

inline Mat<6, 6> svdRotationGradient(const SignedSvd<3, 2> &s) {
  Mat<6, 6> G = Mat<6, 6>::Zero();
  const Mat<3, 2> T = (s.U.col(0) * s.V.col(1).transpose() - s.U.col(1) * s.V.col(0).transpose()) / std::sqrt(2.0);
  const Vec<6> t = flatten<3, 2>(T);
  G += (2.0 / (s.s[0] + s.s[1])) * t * t.transpose();
  for (int j = 0; j < 2; ++j) {
    const Vec<6> q = flatten<3, 2>(Mat<3, 2>(s.U.col(2) * s.V.col(j).transpose()));
    G += (1.0 / s.s[j]) * q * q.transpose();
  }
  return G;
}

// tr(S D) = tr(R^T F D) (I4 for D = aa^T, I6 for the cross tensor) with exact SVD-based derivatives.
template <int D>
inline Derivs<D * D> svdStretchInvariant(const Mat<D, D> &F, const Mat<D, D> &Dm, Order order = Order::Hessian) {
  constexpr int N = D * D;
  const SignedSvd<D, D> s = signedSvd<D>(F);
  const Mat<D, D> Ah = s.V.transpose() * Dm * s.V;  // fiber tensor in the principal frame
  const Mat<D, D> Sig = s.s.asDiagonal();
  Derivs<N> out;
  out.value = Sig.cwiseProduct(Ah).sum();
  if (!wants(order, Order::Gradient)) return out;
  // Twist W1(e_k) for the basis perturbation E = e_k (row-major index k = i*D + j).
  Mat<D, D> W1[N];
  for (int k = 0; k < N; ++k) {
    W1[k].setZero();
    const int i = k / D, j = k % D;
    if (i != j) {
      const double w = 1.0 / (s.s[i] + s.s[j]);
      W1[k](i, j) = w;
      W1[k](j, i) = -w;
    }
  }
  Vec<N> gh;
  for (int k = 0; k < N; ++k) {
    Mat<D, D> Ek = Mat<D, D>::Zero();
    Ek(k / D, k % D) = 1.0;
    gh[k] = ((Ek - W1[k] * Sig) * Ah).trace();
  }
  // Principal frame -> world: dF = U E V^T, so the gradient is U Gh V^T.
  Mat<N, N> T;  // vec(U E V^T) = T vec(E)
  for (int k = 0; k < N; ++k) {
    Mat<D, D> Ek = Mat<D, D>::Zero();
    Ek(k / D, k % D) = 1.0;
    T.col(k) = flatten<D, D>(Mat<D, D>(s.U * Ek * s.V.transpose()));
  }
  out.grad = T * gh;
  if (!wants(order, Order::Hessian)) return out;
  // Second-order term Q(E) = tr((-W1 E - W2 Sig + W1^2 Sig / 2) Ah); its bilinear form by polarization.
  Mat<N, N> Hh;
  auto bilinear = [&](int k, int l) {
    Mat<D, D> Ek = Mat<D, D>::Zero(), El = Mat<D, D>::Zero();
    Ek(k / D, k % D) = 1.0;
    El(l / D, l % D) = 1.0;
    // Symmetrized contributions of the pair (k, l).
    const Mat<D, D> X = 0.5 * (-W1[k] * El - W1[l] * Ek) + 0.25 * (W1[k] * W1[l] + W1[l] * W1[k]) * Sig;
    const Mat<D, D> Y = X - X.transpose();
    Mat<D, D> W2 = Mat<D, D>::Zero();
    for (int i = 0; i < D; ++i)
      for (int j = 0; j < D; ++j)
        if (i != j) W2(i, j) = Y(i, j) / (s.s[i] + s.s[j]);
    return 2.0 * ((X - W2 * Sig) * Ah).trace();
  };
  for (int k = 0; k < N; ++k)
    for (int l = k; l < N; ++l) Hh(k, l) = Hh(l, k) = bilinear(k, l);
  out.hess = T * Hh * T.transpose();
  return out;
}

}  // namespace aries::kernels
