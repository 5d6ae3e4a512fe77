#pragma once
// The indenter poses the tests press with (one definition for every test file).
#include <cmath>

#include "core/geometry/pose.hpp"

namespace sbtest {

// X_EI of a sphere of radius r whose lowest point is `depth` into the gel at (x, y), turned by R.
inline sb::Pose sphere_pose(double r, double x, double y, double depth, const sb::Mat3& R = sb::Mat3::Identity()) {
  sb::Pose X = sb::Pose::Identity();
  X.linear() = R;
  X.translation() = sb::Vec3(x, y, r - depth);
  return X;
}

// The 4 mm sphere of the calibration and residual tests, turned `yaw_deg` about the gel's normal.
inline sb::Pose sphere4mm_pose(double x, double y, double depth, double yaw_deg = 0) {
  return sphere_pose(0.004, x, y, depth, sb::Rz(yaw_deg * M_PI / 180));
}

}  // namespace sbtest
