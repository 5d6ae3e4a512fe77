// The camera models' projection, its Jacobian and the back-projection of an image point (camera.hpp).
#include "core/sensor/camera.hpp"

#include <cmath>

namespace sb {

Vec2 Camera::project(const Vec3& p_E) const {
  if (!pinhole()) return px_from_E(p_E.head<2>());
  const Vec2 n = p_E.head<2>() / (p_E.z() + distance_m);
  return principal_px + focal_px * (1.0 + k1 * n.squaredNorm()) * n;
}

Eigen::Matrix<double, 2, 3> Camera::project_jacobian(const Vec3& p_E) const {
  Eigen::Matrix<double, 2, 3> J = Eigen::Matrix<double, 2, 3>::Zero();
  if (!pinhole()) {
    J(0, 0) = J(1, 1) = px_per_metre();
    return J;
  }
  // uv = c + f g(n) with n = (x, y) / w, w = z + D and g(n) = (1 + k1 |n|^2) n:
  //   dn/dp = [I2 / w, -n / w],  dg/dn = (1 + k1 |n|^2) I2 + 2 k1 n n^T.
  const double w = p_E.z() + distance_m;
  const Vec2 n = p_E.head<2>() / w;
  Eigen::Matrix<double, 2, 3> dn_dp;
  dn_dp << 1.0 / w, 0.0, -n.x() / w, 0.0, 1.0 / w, -n.y() / w;
  const Eigen::Matrix2d dg_dn = (1.0 + k1 * n.squaredNorm()) * Eigen::Matrix2d::Identity() +
                                2.0 * k1 * n * n.transpose();
  return focal_px * dg_dn * dn_dp;
}

std::optional<Camera::Ray> Camera::back_project(const Vec2& uv) const {
  if (!pinhole()) {
    const Vec2 xy = E_from_px(uv);
    return Ray{Vec3(xy.x(), xy.y(), 0.0), Vec3(0.0, 0.0, -1.0)};
  }
  // Invert the radial map r_d = r (1 + k1 r^2) for r by Newton's method from r = r_d; the distorted and the
  // undistorted point lie on the same radius, so n = d * r / r_d.
  const Vec2 d = (uv - principal_px) / focal_px;
  const double rd = d.norm();
  double r = rd;
  constexpr int kNewtonIterations = 30;
  constexpr double kRadiusTolerance = 1e-15;  // normalised units: far below a pixel for any focal length
  for (int i = 0; i < kNewtonIterations && rd > 0.0; ++i) {
    const double residual = r * (1.0 + k1 * r * r) - rd;
    const double slope = 1.0 + 3.0 * k1 * r * r;
    if (slope <= 0.0) return std::nullopt;  // beyond the radius where the distortion folds over
    const double step = residual / slope;
    r -= step;
    if (std::abs(step) < kRadiusTolerance) break;
  }
  if (!(r >= 0.0) || std::abs(r * (1.0 + k1 * r * r) - rd) > 1e-12) return std::nullopt;
  const Vec2 n = rd > 0.0 ? Vec2(d * (r / rd)) : Vec2::Zero();
  return Ray{Vec3(0.0, 0.0, -distance_m), Vec3(n.x(), n.y(), 1.0).normalized()};
}

}  // namespace sb
