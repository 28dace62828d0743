// Shared vocabulary of the kernel layer: element shapes, row-major flattening of F, and the value/gradient/Hessian
// bundle that every invariant and energy returns.
//
// Conventions (a contract for every file in lib/kernels and lib/energies):
//  * F is Rows x Cols: 3x3 (tetrahedron), 2x2 (planar triangle), 3x2 (cloth triangle in 3D).
//  * Gradients w.r.t. F are flattened row-major: index(i, j) = i * Cols + j. Hessians are (Rows*Cols)^2 in the
//    same ordering. unflatten() turns a gradient back into the PK1 matrix of the same shape as F.
//  * Nothing here allocates: all matrices are fixed-size Eigen types.
#pragma once

#include <Eigen/Dense>

#include <cmath>
#include <limits>
#include <type_traits>

namespace aries::kernels {

template <int R, int C>
using Mat = Eigen::Matrix<double, R, C>;
template <int N>
using Vec = Eigen::Matrix<double, N, 1>;

// Selects the overload of a kernel for one shape of F: `template <int R, int C, IfShape<R, C, 3, 3> = 0>`. The kernels
// whose bodies run Eigen's eigensolvers or SVDs (rootValue's 3x3 fallback, signedSvd on 3x2, the closed-form and the
// numeric Hessian filters), and the kernels that call them, are templates so that only a translation unit that calls
// them instantiates those solvers: clang and GCC instantiate what the body of a non-template inline function uses in
// every file that includes it, called or not. Three of them (the 4x4 and 9x9 eigensolvers, the 3x2 SVD) cost 4-5 s of
// clang's front end each in every file that included energies/energy.hpp (lib/energies/material.cpp: 26 s to 7.5 s).
// Since then aries' own build also compiles the solvers themselves once (kernels/dense_decompositions.hpp); the
// templates still keep the kernels' own bodies, and the solvers for users of the installed headers, out of the files
// that do not call them.
template <int R, int C, int Rows, int Cols>
using IfShape = std::enable_if_t<R == Rows && C == Cols, int>;

// How much of an evaluation a caller needs: line searches only need values, assembly needs everything.
enum class Order : int { Value = 0, Gradient = 1, Hessian = 2 };
constexpr bool wants(Order have, Order need) { return static_cast<int>(have) >= static_cast<int>(need); }

// A scalar function of F with its first and second derivatives (flattened row-major).
template <int N>
struct Derivs {
  double value = 0.0;
  Vec<N> grad = Vec<N>::Zero();
  Mat<N, N> hess = Mat<N, N>::Zero();

  Derivs &operator+=(const Derivs &o) {
    value += o.value;
    grad += o.grad;
    hess += o.hess;
    return *this;
  }
  Derivs &scale(double s) {
    value *= s;
    grad *= s;
    hess *= s;
    return *this;
  }
};

template <int R, int C>
inline Vec<R * C> flatten(const Mat<R, C> &M) {
  Vec<R * C> v;
  for (int i = 0; i < R; ++i)
    for (int j = 0; j < C; ++j) v[i * C + j] = M(i, j);
  return v;
}

template <int R, int C>
inline Mat<R, C> unflatten(const Vec<R * C> &v) {
  Mat<R, C> M;
  for (int i = 0; i < R; ++i)
    for (int j = 0; j < C; ++j) M(i, j) = v[i * C + j];
  return M;
}

// Chain rule for psi(z_1..z_K) with z_k(F) (paper Eqs. 18-19):
//   d psi/dF   = sum_k psi_k dz_k/dF
//   d2 psi/dF2 = sum_k psi_k d2 z_k/dF2 + sum_kl psi_kl dz_k/dF (x) dz_l/dF.
// `first` holds psi_k, `second` the symmetric psi_kl; the Hessian part is assembled as G * second * G^T.
template <int N, int K>
inline void accumulateChain(Derivs<N> &out, const Derivs<N> *const (&z)[K], const Vec<K> &first,
                            const Mat<K, K> &second, Order order) {
  if (!wants(order, Order::Gradient)) return;
  Mat<N, K> G;
  for (int k = 0; k < K; ++k) G.col(k) = z[k]->grad;
  out.grad.noalias() += G.lazyProduct(first);
  if (!wants(order, Order::Hessian)) return;
  for (int k = 0; k < K; ++k)
    if (first[k] != 0.0) out.hess.noalias() += first[k] * z[k]->hess;
  // Small fixed-size products: coefficient-wise evaluation beats Eigen's blocked GEMM path here.
  const Mat<N, K> GS = G.lazyProduct(second);
  out.hess.noalias() += GS.lazyProduct(G.transpose());
}

// Scalar composition h(g(F)) with h', h'' known.
template <int N>
inline Derivs<N> compose(const Derivs<N> &g, double h, double dh, double d2h, Order order) {
  Derivs<N> out;
  out.value = h;
  if (wants(order, Order::Gradient)) out.grad = dh * g.grad;
  if (wants(order, Order::Hessian)) out.hess = dh * g.hess + d2h * g.grad * g.grad.transpose();
  return out;
}

// Product a(F) * b(F).
template <int N>
inline Derivs<N> product(const Derivs<N> &a, const Derivs<N> &b, Order order) {
  Derivs<N> out;
  out.value = a.value * b.value;
  if (wants(order, Order::Gradient)) out.grad = a.value * b.grad + b.value * a.grad;
  if (wants(order, Order::Hessian))
    out.hess = a.value * b.hess + b.value * a.hess + a.grad * b.grad.transpose() + b.grad * a.grad.transpose();
  return out;
}

constexpr double kEps = std::numeric_limits<double>::epsilon();

}  // namespace aries::kernels
