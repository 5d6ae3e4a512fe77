#pragma once
// Rigid transforms with frame-labelled names (Drake's monogram notation):
//   X_AB  pose of frame B measured in frame A;  p_AQ  point Q measured in A;  R_AB rotation of B in A.
//   X_AC = X_AB * X_BC;  p_AQ = X_AB * p_BQ;  X_BA = X_AB.inverse().
// Frames used throughout: E elastomer (tsd/1: origin at the centre of the gel surface, +z out of the gel),
// I indenter (its mesh frame), W world.
#include <Eigen/Geometry>
#include <array>
#include <string>

#include "core/base/error.hpp"

namespace sb {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;
using Pose = Eigen::Isometry3d;

// Relative tolerance on |q| - 1 above which a read quaternion is reported as non-unit.
inline constexpr double kQuatUnitTolerance = 1e-6;
// Below this norm a quaternion carries no rotation and is rejected.
inline constexpr double kQuatMinNorm = 1e-9;

// Pose from a translation and a w-first quaternion (the tsd/1 column order).
Pose make_pose(const Vec3& p, const Quat& q);
Pose make_pose(const Vec3& p, double qw, double qx, double qy, double qz);

// Normalises a quaternion read from a file. Throws InputError(where) for a zero-norm or non-finite one;
// adds a warning for one whose norm differs from 1 by more than kQuatUnitTolerance.
Quat normalized_quaternion(double qw, double qx, double qy, double qz, const std::string& where, Warnings* warnings);

// Rotation about a unit axis by an angle (right-handed), and the common elementary ones.
Mat3 rotation_about(const Vec3& axis, double angle_rad);
Mat3 Rx(double a);
Mat3 Ry(double a);
Mat3 Rz(double a);

// The in-plane (z) component of the rotation vector of R; used by FOTS's SE(2) projection.
double rotation_vector_z(const Mat3& R);

// w-first array of the pose's quaternion, hemisphere with w >= 0.
std::array<double, 4> quaternion_wxyz(const Pose& X);

bool is_finite(const Pose& X);

}  // namespace sb
