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
