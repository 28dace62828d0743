// Contact with analytic obstacles (ground plane, sphere) as a smooth log barrier on the vertex-obstacle distance d,
// in the style of incremental potential contact (Li et al. 2020, the paper's reference for Eq. 34):
//   b(d) = -(d - dhat)^2 ln(d / dhat)   for 0 < d < dhat,   0 for d >= dhat,   +inf for d <= 0,
// C2 at dhat. A vertex's energy is kappa b(d(x)); gradient kappa b'(d) grad d (exact). Hessian: kappa b''(d) grad d
// grad d^T + kappa b'(d) hess d; b'' > 0 and b' < 0 on (0, dhat), and hess d is PSD for a sphere (zero for a plane),
// so the second term is negative semi-definite and is dropped: the returned Hessian is the PSD projection.
// An infinite energy at d <= 0 makes the line search reject any step that crosses the surface.
#pragma once

#include "kernels/types.hpp"

namespace aries::kernels {

struct Obstacle {
  enum class Kind { Plane, Sphere } kind = Kind::Plane;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();   // plane: a point on it; sphere: the center
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // plane: unit normal pointing to the free side
  double radius = 0.0;                                // sphere
};

// Signed distance and its gradient (positive on the free side).
inline double obstacleDistance(const Obstacle &o, const Eigen::Vector3d &x, Eigen::Vector3d *grad) {
  if (o.kind == Obstacle::Kind::Plane) {
    if (grad) *grad = o.normal;
    return o.normal.dot(x - o.point);
  }
  const Eigen::Vector3d r = x - o.point;
  const double n = r.norm();
  if (grad) *grad = n > 0.0 ? Eigen::Vector3d(r / n) : Eigen::Vector3d::UnitZ();
  return n - o.radius;
}

inline Derivs<3> obstacleBarrier(const Obstacle &o, const Eigen::Vector3d &x, double dhat, double kappa,
                                 Order order = Order::Hessian) {
  Derivs<3> out;
  Eigen::Vector3d g;
  const double d = obstacleDistance(o, x, &g);
  if (d >= dhat) return out;
  if (!(d > 0.0)) {
    out.value = std::numeric_limits<double>::infinity();
    return out;
  }
  const double t = d - dhat, L = std::log(d / dhat);
  out.value = -kappa * t * t * L;
  const double b1 = -2.0 * t * L - t * t / d;
  const double b2 = -2.0 * L - 4.0 * t / d + t * t / (d * d);
  if (wants(order, Order::Gradient)) out.grad = kappa * b1 * g;
  if (wants(order, Order::Hessian)) out.hess = kappa * b2 * g * g.transpose();
  return out;
}

}  // namespace aries::kernels
