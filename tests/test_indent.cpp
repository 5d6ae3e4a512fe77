#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "core/geometry/indent.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_indent {

using namespace sb;

namespace {
constexpr double kTolM = 5e-6;  // indent_down stops within 2 um of the surface; 5 um covers it
}

TEST_CASE("indent_down: a sphere pressed into a flat surface leaves its spherical cap", "[indent]") {
  // Sphere radius R = 4 mm, centre at z = R - 1 mm: 1 mm deep. Under the centre the surface goes to
  // -1 mm; at r = 2 mm to c - sqrt(R^2 - r^2) = 3 - sqrt(12) = -0.4641 mm; at r = 3 mm,
  // 3 - sqrt(7) = +0.354 mm > 0: outside the contact (radius sqrt(R^2 - c^2) = sqrt(7) = 2.646 mm), stays at 0.
  const double R = 4e-3, c = 3e-3;
  const auto sphere = make_sphere_sdf(R);
  const Pose X_EI = make_pose(Vec3(0.5e-3, -0.2e-3, c), Quat::Identity());
  std::vector<Vec3> p = {Vec3(0.5e-3, -0.2e-3, 0), Vec3(2.5e-3, -0.2e-3, 0), Vec3(0.5e-3, 2.8e-3, 0)};
  CHECK(indent_down(*sphere, X_EI, p) == 2);
  CHECK(std::abs(p[0].z() - (-1e-3)) < kTolM);
  CHECK(std::abs(p[1].z() - (c - std::sqrt(R * R - 4e-6))) < kTolM);
  CHECK(p[2].z() == 0.0);
  CHECK(p[1].x() == 2.5e-3);  // straight down: x, y unchanged
}

TEST_CASE("indent_down follows a tilted indenter's lower face, not its far side", "[indent]") {
  // A 10 mm cube rotated 30 degrees about x, its centre 4 mm above the surface: its lowest edge lies
  // 5 (cos 30 + sin 30) - 4 = 2.83 mm deep along the x axis. Under the edge (y = 0) the point goes to
  // the edge's depth; the two lower faces meet there, the top face is 6.8 mm higher.
  const auto box = make_box_sdf(Vec3(10e-3, 10e-3, 10e-3));
  const double a = 30.0 * M_PI / 180.0;
  const Pose X_EI = make_pose(Vec3(0, 0, 4e-3), Quat(Eigen::AngleAxisd(a, Vec3::UnitX())));
  // Lowest edge: the corner direction (0, -5, -5) rotated by a about x -> z = -5 cos a - 5 sin a (mm), at y = 5 sin a -
  // 5 cos a.
  const double y_edge = (5 * std::sin(a) - 5 * std::cos(a)) * 1e-3;
  const double z_edge = 4e-3 - 5e-3 * (std::cos(a) + std::sin(a));
  std::vector<Vec3> p = {Vec3(1e-3, y_edge, 0)};
  CHECK(indent_down(*box, X_EI, p) == 1);
  CHECK(std::abs(p[0].z() - z_edge) < kTolM);
}

}  // namespace test_indent
