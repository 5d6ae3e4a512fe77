#include "core/geometry/pose.hpp"

#include <cmath>
#include <sstream>

namespace sb {

Pose make_pose(const Vec3& p, const Quat& q) {
  Pose X = Pose::Identity();
  X.linear() = q.normalized().toRotationMatrix();
  X.translation() = p;
  return X;
}

Pose make_pose(const Vec3& p, double qw, double qx, double qy, double qz) { return make_pose(p, Quat(qw, qx, qy, qz)); }

Quat normalized_quaternion(double qw, double qx, double qy, double qz, const std::string& where, Warnings* warnings) {
  const double n2 = qw * qw + qx * qx + qy * qy + qz * qz;
  if (!std::isfinite(n2)) throw InputError(where, "quaternion has a non-finite component");
  const double n = std::sqrt(n2);
  if (n < kQuatMinNorm) throw InputError(where, "quaternion has zero norm");
  if (std::abs(n - 1.0) > kQuatUnitTolerance && warnings) {
    std::ostringstream s;
    s << where << ": quaternion norm " << n << " is not 1; normalised";
    warnings->add(s.str());
  }
  return Quat(qw / n, qx / n, qy / n, qz / n);
}

Mat3 rotation_about(const Vec3& axis, double angle_rad) {
  return Eigen::AngleAxisd(angle_rad, axis.normalized()).toRotationMatrix();
}
Mat3 Rx(double a) { return rotation_about(Vec3::UnitX(), a); }
Mat3 Ry(double a) { return rotation_about(Vec3::UnitY(), a); }
Mat3 Rz(double a) { return rotation_about(Vec3::UnitZ(), a); }

double rotation_vector_z(const Mat3& R) {
  const Eigen::AngleAxisd aa(R);
  return (aa.axis() * aa.angle()).z();
}

std::array<double, 4> quaternion_wxyz(const Pose& X) {
  Quat q(X.linear());
  if (q.w() < 0) q.coeffs() *= -1.0;
  return {q.w(), q.x(), q.y(), q.z()};
}

bool is_finite(const Pose& X) { return X.matrix().allFinite(); }

}  // namespace sb
