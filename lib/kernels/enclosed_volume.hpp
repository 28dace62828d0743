// The volume a closed triangulated surface encloses, one triangle at a time: the signed volume of the tetrahedron
// (c, x0, x1, x2), v = (x0 - c) . ((x1 - c) x (x2 - c)) / 6, with its gradient and Hessian in the positions
// (vertex-major: x0, x1, x2). Summed over a closed surface whose triangles are ordered with outward normals
// ((x1 - x0) x (x2 - x0) outward) it is the enclosed volume, for any reference point c; c only sets the size of the
// pieces (their round-off). The potential of a follower pressure p on a closed surface is p V(x) with the body's
// outward normals (fem/terms/follower_pressure.hpp). Cubic in x: the Hessian is linear and trace-free (indefinite).
#pragma once

#include "kernels/types.hpp"

namespace aries::kernels {

// [a]x: the matrix with [a]x b = a x b.
inline Eigen::Matrix3d crossMatrix(const Eigen::Vector3d &a) {
  Eigen::Matrix3d m;
  m << 0.0, -a[2], a[1], a[2], 0.0, -a[0], -a[1], a[0], 0.0;
  return m;
}

inline Derivs<9> triangleVolume(const Eigen::Vector3d &x0, const Eigen::Vector3d &x1, const Eigen::Vector3d &x2,
                                const Eigen::Vector3d &c, Order order = Order::Hessian) {
  const Eigen::Vector3d a = x0 - c, b = x1 - c, d = x2 - c;
  Derivs<9> out;
  out.value = a.dot(b.cross(d)) / 6.0;
  if (!wants(order, Order::Gradient)) return out;
  out.grad.segment<3>(0) = b.cross(d) / 6.0;
  out.grad.segment<3>(3) = d.cross(a) / 6.0;
  out.grad.segment<3>(6) = a.cross(b) / 6.0;
  if (!wants(order, Order::Hessian)) return out;
  // d/dx1 of b x d = -[d]x, d/dx2 of b x d = [b]x; the blocks of the other two rows follow by the cyclic symmetry.
  const Eigen::Matrix3d A = crossMatrix(a) / 6.0, B = crossMatrix(b) / 6.0, D = crossMatrix(d) / 6.0;
  out.hess.block<3, 3>(0, 3) = -D;
  out.hess.block<3, 3>(0, 6) = B;
  out.hess.block<3, 3>(3, 0) = D;
  out.hess.block<3, 3>(3, 6) = -A;
  out.hess.block<3, 3>(6, 0) = -B;
  out.hess.block<3, 3>(6, 3) = A;
  return out;
}

}  // namespace aries::kernels

namespace aries::kernels {

// The boundary faces of the volume elements as parametric patches x(u, v) = sum_a N_a(u, v) x_a, with a quadrature
// rule that integrates (x - c) . (x_u x x_v) exactly: that integrand has degree 1 on a linear triangle (tet faces), 2
// in each of u and v on a bilinear quadrangle (hexahedron faces), 4 on a quadratic triangle (P2 tet faces). Node
// orders: a triangle's corners, then (Tri6) the nodes on edges 01, 12, 20 (gmsh's 6-node triangle); a quadrangle's
// corners in cyclic order. `point(q, N, Nu, Nv)` gives the shape functions and their parameter derivatives at point q
// and returns its weight (reference area included).
namespace face {

struct Tri3 {
  static constexpr int kNodes = 3, kPoints = 1;
  static double point(int, Vec<3> *N, Vec<3> *Nu, Vec<3> *Nv) {
    *N = Vec<3>::Constant(1.0 / 3.0);
    *Nu << -1.0, 1.0, 0.0;
    *Nv << -1.0, 0.0, 1.0;
    return 0.5;  // the centroid rule: exact for degree 1
  }
};

struct Quad4 {
  static constexpr int kNodes = 4, kPoints = 4;
  static double point(int q, Vec<4> *N, Vec<4> *Nu, Vec<4> *Nv) {
    constexpr double corner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    const double g = 1.0 / std::sqrt(3.0), u = corner[q][0] * g, v = corner[q][1] * g;
    for (int a = 0; a < 4; ++a) {
      (*N)[a] = (1 + corner[a][0] * u) * (1 + corner[a][1] * v) / 4.0;
      (*Nu)[a] = corner[a][0] * (1 + corner[a][1] * v) / 4.0;
      (*Nv)[a] = corner[a][1] * (1 + corner[a][0] * u) / 4.0;
    }
    return 1.0;  // 2x2 Gauss on [-1, 1]^2: exact for degree 3 in each of u and v
  }
};

struct Tri6 {
  static constexpr int kNodes = 6, kPoints = 6;
  // The symmetric 6-point rule of degree 4 (Strang & Fix 1973; Dunavant 1985, Table I, p = 4): barycentrics
  // (1 - 2a, a, a) and their rotations, weights relative to the area.
  static double point(int q, Vec<6> *N, Vec<6> *Nu, Vec<6> *Nv) {
    constexpr double a[2] = {0.445948490915965, 0.091576213509771};
    constexpr double w[2] = {0.223381589678011, 0.109951743655322};
    const int orbit = q / 3, turn = q % 3;
    double L[3] = {a[orbit], a[orbit], a[orbit]};
    L[turn] = 1.0 - 2.0 * a[orbit];
    const double L0 = L[0], L1 = L[1], L2 = L[2];  // L1 = u, L2 = v, L0 = 1 - u - v
    *N << L0 * (2 * L0 - 1), L1 * (2 * L1 - 1), L2 * (2 * L2 - 1), 4 * L0 * L1, 4 * L1 * L2, 4 * L2 * L0;
    *Nu << -(4 * L0 - 1), 4 * L1 - 1, 0.0, 4 * (L0 - L1), 4 * L2, -4 * L2;
    *Nv << -(4 * L0 - 1), 0.0, 4 * L2 - 1, -4 * L1, 4 * L1, 4 * (L0 - L2);
    return 0.5 * w[orbit];
  }
};

}  // namespace face

// The volume a face contributes to the volume enclosed by a closed surface of such faces, (1/3) int (x - c) . n da
// with n da = x_u x x_v du dv (divergence theorem: div (x - c) = 3), with its gradient and Hessian in the node
// positions x (row a = node a; vertex-major flattening). The integrand f = a . (b x d), a = x - c, b = x_u, d = x_v, is
// trilinear in (a, b, d), each linear in the nodes: its gradient at node A is N_A (b x d) + N_A,u (d x a) +
// N_A,v (a x b), and its Hessian block (A, B) is N_A N_B,u (-[d]x) + N_A N_B,v [b]x + N_A,u N_B [d]x - N_A,v N_B [b]x
// - N_A,u N_B,v [a]x + N_A,v N_B,u [a]x (symmetric). On a linear triangle it equals triangleVolume.
template <class Face>
inline Derivs<3 * Face::kNodes> faceVolume(const Mat<Face::kNodes, 3> &x, const Eigen::Vector3d &c,
                                           Order order = Order::Hessian) {
  constexpr int K = Face::kNodes;
  Derivs<3 * K> out;
  for (int q = 0; q < Face::kPoints; ++q) {
    Vec<K> N, Nu, Nv;
    const double w = Face::point(q, &N, &Nu, &Nv) / 3.0;
    const Eigen::Vector3d a = x.transpose() * N - c, b = x.transpose() * Nu, d = x.transpose() * Nv;
    const Eigen::Vector3d bd = b.cross(d), da = d.cross(a), ab = a.cross(b);
    out.value += w * a.dot(bd);
    if (!wants(order, Order::Gradient)) continue;
    for (int A = 0; A < K; ++A) out.grad.template segment<3>(3 * A) += w * (N[A] * bd + Nu[A] * da + Nv[A] * ab);
    if (!wants(order, Order::Hessian)) continue;
    const Eigen::Matrix3d ca = crossMatrix(a), cb = crossMatrix(b), cd = crossMatrix(d);
    for (int A = 0; A < K; ++A)
      for (int B = 0; B < K; ++B)
        out.hess.template block<3, 3>(3 * A, 3 * B) +=
            w * ((N[A] * Nv[B] - Nv[A] * N[B]) * cb + (Nu[A] * N[B] - N[A] * Nu[B]) * cd +
                 (Nv[A] * Nu[B] - Nu[A] * Nv[B]) * ca);
  }
  return out;
}

// The area moments of a face at rest, row A = int N_A n dA = int N_A (X_u x X_v) du dv (exact by the same rules): the
// consistent nodal forces of a dead pressure p are -p times them (kernels' orientation: n as the node order gives it).
template <class Face>
inline Mat<Face::kNodes, 3> faceAreaMoments(const Mat<Face::kNodes, 3> &X) {
  Mat<Face::kNodes, 3> m = Mat<Face::kNodes, 3>::Zero();
  for (int q = 0; q < Face::kPoints; ++q) {
    Vec<Face::kNodes> N, Nu, Nv;
    const double w = Face::point(q, &N, &Nu, &Nv);
    const Eigen::Vector3d n = (X.transpose() * Nu).cross(X.transpose() * Nv);
    m += w * N * n.transpose();
  }
  return m;
}

// The shares of a face's rest area, entry A = int N_A dA = int N_A |X_u x X_v| du dv (the consistent nodal loads of a
// unit traction; exact on flat faces, to the rule's degree on curved ones): A / 3 per corner of a flat triangle; 0 at
// the corners and A / 3 at the edge nodes of a flat 6-node triangle.
template <class Face>
inline Vec<Face::kNodes> faceAreaShares(const Mat<Face::kNodes, 3> &X) {
  Vec<Face::kNodes> s = Vec<Face::kNodes>::Zero();
  for (int q = 0; q < Face::kPoints; ++q) {
    Vec<Face::kNodes> N, Nu, Nv;
    const double w = Face::point(q, &N, &Nu, &Nv);
    s += w * (X.transpose() * Nu).cross(X.transpose() * Nv).norm() * N;
  }
  return s;
}

}  // namespace aries::kernels
