// Discrete bending of cloth on interior edges: the isometric quadratic bending model of Bergou et al. 2006
// ("A quadratic bending model for inextensible surfaces"), for surfaces that are flat at rest.
//
// A hinge is the edge (x0, x1) with the opposite vertices x2, x3 of its two triangles. With the rest cotangents
//   c01 = cot angle(e0, e1), c02 = cot angle(e0, e2), c03 = cot angle(-e0, e3), c04 = cot angle(-e0, e4),
//   e0 = x1 - x0, e1 = x2 - x0, e2 = x3 - x0, e3 = x2 - x1, e4 = x3 - x1,
// the hinge vector K = (c03 + c04, c01 + c02, -c01 - c03, -c02 - c04) and the rest areas A0, A1 of the two triangles,
//   E = k/2 * 3 / (A0 + A1) * | sum_i K_i x_i |^2,
// a discrete integral of the squared mean curvature: zero for any rigid or planar isometric placement of a flat
// rest hinge, exact gradient (linear in x) and a constant PSD Hessian (k 3/(A0+A1) K K^T (x) I3).
#pragma once

#include "kernels/types.hpp"

namespace aries::kernels {

struct BendingHinge {
  Eigen::Vector4d K = Eigen::Vector4d::Zero();  // hinge vector
  double weight = 0.0;                          // 3 / (A0 + A1)
};

namespace detail {
inline double cotangent(const Eigen::Vector3d &u, const Eigen::Vector3d &v) {
  const double s = u.cross(v).norm();
  return s > 0.0 ? u.dot(v) / s : 0.0;
}
}  // namespace detail

// Rest data of a hinge from its rest positions (x0, x1 the edge; x2, x3 the opposite vertices).
inline BendingHinge bendingHinge(const Eigen::Vector3d &x0, const Eigen::Vector3d &x1, const Eigen::Vector3d &x2,
                                 const Eigen::Vector3d &x3) {
  const Eigen::Vector3d e0 = x1 - x0, e1 = x2 - x0, e2 = x3 - x0, e3 = x2 - x1, e4 = x3 - x1;
  const double c01 = detail::cotangent(e0, e1), c02 = detail::cotangent(e0, e2);
  const double c03 = detail::cotangent(-e0, e3), c04 = detail::cotangent(-e0, e4);
  BendingHinge h;
  h.K << c03 + c04, c01 + c02, -c01 - c03, -c02 - c04;
  const double area = 0.5 * (e0.cross(e1).norm() + e0.cross(e2).norm());
  h.weight = area > 0.0 ? 3.0 / area : 0.0;
  return h;
}

// Energy, gradient (12: vertex-major x0..x3) and Hessian (12x12) of one hinge with stiffness k.
inline Derivs<12> quadraticBending(const BendingHinge &h, const Eigen::Vector3d (&x)[4], double k,
                                   Order order = Order::Hessian) {
  Derivs<12> out;
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  for (int i = 0; i < 4; ++i) v += h.K[i] * x[i];
  const double c = k * h.weight;
  out.value = 0.5 * c * v.squaredNorm();
  if (wants(order, Order::Gradient))
    for (int i = 0; i < 4; ++i) out.grad.segment<3>(3 * i) = c * h.K[i] * v;
  if (wants(order, Order::Hessian))
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) out.hess.block<3, 3>(3 * i, 3 * j) = c * h.K[i] * h.K[j] * Eigen::Matrix3d::Identity();
  return out;
}

}  // namespace aries::kernels
