#include <catch2/catch.hpp>
#include <cmath>

#include "core/geometry/pose.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_pose {

using namespace sb;

namespace {
constexpr double kTol = 1e-12;  // pure double arithmetic on O(1) numbers
}

TEST_CASE("pose composition follows the frame algebra X_AC = X_AB * X_BC", "[pose]") {
  // X_AB: rotate 90 deg about z, then translate (1, 0, 0). X_BC: translate (0, 2, 0).
  // A point at C's origin is at (0, 2, 0) in B; rotated by Rz(90) it is (-2, 0, 0); plus (1, 0, 0)
  // gives p_AC = (-1, 0, 0).
  const Pose X_AB = make_pose(Vec3(1, 0, 0), Quat(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ())));
  const Pose X_BC = make_pose(Vec3(0, 2, 0), Quat::Identity());
  const Pose X_AC = X_AB * X_BC;
  CHECK((X_AC.translation() - Vec3(-1, 0, 0)).norm() < kTol);
  // Inverse: X_CA * X_AC = identity.
  const Pose I = X_AC.inverse() * X_AC;
  CHECK((I.matrix() - Eigen::Matrix4d::Identity()).norm() < kTol);
}

TEST_CASE("quaternions from files are w-first and normalised", "[pose]") {
  Warnings w;
  // (2, 0, 0, 0) has norm 2: the identity after normalisation, with a warning.
  const Quat q = normalized_quaternion(2, 0, 0, 0, "poses.csv:3", &w);
  CHECK(std::abs(q.w() - 1.0) < kTol);
  CHECK(w.messages.size() == 1);
  CHECK(w.messages[0].find("poses.csv:3") != std::string::npos);
  // A unit quaternion (cos 45deg, 0, 0, sin 45deg) = 90 deg about z: no warning.
  Warnings none;
  const Quat qz = normalized_quaternion(std::sqrt(0.5), 0, 0, std::sqrt(0.5), "x", &none);
  CHECK(none.empty());
  CHECK((qz.toRotationMatrix() * Vec3::UnitX() - Vec3::UnitY()).norm() < 1e-12);
}

TEST_CASE("zero-norm and non-finite quaternions are rejected with their location", "[pose]") {
  CHECK_THROWS_WITH(normalized_quaternion(0, 0, 0, 0, "poses.csv:7:6", nullptr),
                    Catch::Contains("poses.csv:7:6") && Catch::Contains("zero norm"));
  CHECK_THROWS_AS(normalized_quaternion(NAN, 0, 0, 1, "p", nullptr), InputError);
}

TEST_CASE("rotation_vector_z measures in-plane twist", "[pose]") {
  // Rz(0.3) has rotation vector (0, 0, 0.3).
  CHECK(std::abs(rotation_vector_z(Rz(0.3)) - 0.3) < 1e-12);
  // A pure roll about x has no z component.
  CHECK(std::abs(rotation_vector_z(Rx(0.4))) < 1e-12);
}

TEST_CASE("quaternion_wxyz returns the w >= 0 hemisphere", "[pose]") {
  const Pose X = make_pose(Vec3::Zero(), Quat(-std::sqrt(0.5), 0, 0, -std::sqrt(0.5)));
  const auto q = quaternion_wxyz(X);
  CHECK(q[0] >= 0);
  CHECK(std::abs(q[3] - std::sqrt(0.5)) < kTol);
}

}  // namespace test_pose
