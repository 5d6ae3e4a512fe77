#include "core/workbench/value_check.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

// This file's names in a namespace of its own: the unity build compiles several test files as one unit.
namespace test_value_check {

using sb::ParamSpec;
using sb::Pose;
using sb::Vec3;

constexpr double kGel_m = 0.0045;  // the GelSight Mini's gel (GelSpec's default)

Pose at_z(double z_m) {
  Pose X = Pose::Identity();
  X.translation() = Vec3(0.001, -0.002, z_m);
  return X;
}

TEST_CASE("an indenter pose inside the gel's thickness and the reach is accepted", "[value_check]") {
  CHECK(sb::check_indenter_pose(at_z(0.0), kGel_m).accepted);
  CHECK(sb::check_indenter_pose(at_z(-0.004), kGel_m).accepted);  // 4 mm in, of 4.5
  CHECK(sb::check_indenter_pose(at_z(0.030), kGel_m).accepted);   // 30 mm above, of a 40 mm reach
  CHECK(sb::check_indenter_pose(at_z(0.030), kGel_m).message.empty());
}

TEST_CASE("a pose below the gel's back is refused, naming the value, the limit and the unit", "[value_check]") {
  const sb::PoseCheck c = sb::check_indenter_pose(at_z(-0.020), kGel_m);
  CHECK_FALSE(c.accepted);
  CHECK(c.message.find("z = -20 mm is below the gel's back (4.5 mm thick)") == 0);
  // The limit is the gel given, not a constant: a 2 mm gel refuses 3 mm in, which a 4.5 mm gel accepts.
  CHECK_FALSE(sb::check_indenter_pose(at_z(-0.003), 0.002).accepted);
  CHECK(sb::check_indenter_pose(at_z(-0.003), kGel_m).accepted);
}

TEST_CASE("a pose beyond the reach or not a number is refused", "[value_check]") {
  const sb::PoseCheck far = sb::check_indenter_pose(at_z(1e6), kGel_m);  // z = 1e9 mm
  CHECK_FALSE(far.accepted);
  CHECK(far.message.find("z = 1e+09 mm is above the indenter's reach (40 mm above the gel)") == 0);
  Pose X = at_z(0.0);
  X.translation().x() = std::numeric_limits<double>::quiet_NaN();
  CHECK_FALSE(sb::check_indenter_pose(X, kGel_m).accepted);
  X = at_z(0.0);
  X.linear()(0, 0) = std::numeric_limits<double>::infinity();
  CHECK_FALSE(sb::check_indenter_pose(X, kGel_m).accepted);
}

ParamSpec kappa_d() {
  return {.name = "kappa_d", .unit = "px/m", .default_value = 10, .min = 1, .max = 1e9, .help = ""};
}

TEST_CASE("a parameter outside its range is clamped with a note, never silently", "[value_check]") {
  const sb::ParamCheck below = sb::check_param_value(kappa_d(), -5);
  CHECK(below.accepted);
  CHECK(below.value == 1);
  CHECK(below.note == "kappa_d: -5 is below its bound 1; set to 1");
  const sb::ParamCheck above = sb::check_param_value(kappa_d(), 2e9);
  CHECK(above.value == 1e9);
  CHECK(above.note == "kappa_d: 2e+09 is above its bound 1e+09; set to 1e+09");
  const sb::ParamCheck inside = sb::check_param_value(kappa_d(), 40);
  CHECK(inside.value == 40);
  CHECK(inside.note.empty());
  const sb::ParamCheck nan = sb::check_param_value(kappa_d(), std::nan(""));
  CHECK_FALSE(nan.accepted);
  CHECK_FALSE(nan.note.empty());
}

TEST_CASE("a value within the margin of a bound is at bound", "[value_check]") {
  // mu in [0, 5], linear: the margin is 1e-3 x 5 = 0.005; a fit stopped at 5 (issue 52) is at bound.
  const ParamSpec mu{.name = "mu", .unit = "", .default_value = 0.5, .min = 0, .max = 5, .help = ""};
  CHECK(sb::at_bound(mu, 5.0));
  CHECK(sb::at_bound(mu, 4.996));
  CHECK_FALSE(sb::at_bound(mu, 4.99));
  CHECK(sb::at_bound(mu, 0.004));
  CHECK_FALSE(sb::at_bound(mu, 0.5));
  // Log scale over [1, 1e9]: the margin is 1e-3 x ln(1e9) = 0.0207 in ln, a ratio of e^0.0207 = 1.021 to a bound.
  ParamSpec k = kappa_d();
  k.log_scale = true;
  CHECK(sb::at_bound(k, 1.02));
  CHECK_FALSE(sb::at_bound(k, 1.03));
  CHECK(sb::at_bound(k, 1e9 / 1.02));
  CHECK_FALSE(sb::at_bound(k, 1e5));
  ParamSpec on{.name = "on", .unit = "", .default_value = 0, .min = 0, .max = 1, .help = ""};
  on.is_switch = true;
  CHECK_FALSE(sb::at_bound(on, 1));
}

}  // namespace test_value_check
