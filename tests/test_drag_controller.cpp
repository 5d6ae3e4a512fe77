#include "core/workbench/drag_controller.hpp"

#include <catch2/catch.hpp>
#include <cmath>

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_drag_controller {

using sb::DragController;
using sb::DragMode;
using sb::PickRay;
using sb::Pose;
using sb::Vec2;
using sb::Vec3;

// Poses are compared to 1e-12 (metres, radians): the expected values are the same few products and sums
// the controller computes, so only rounding separates them.
constexpr double kTol = 1e-12;

// A parallel-projection camera looking along `forward` (unit), with `right` (unit, perpendicular to it) the
// screen's +x and s mm per pixel: pixel (u, v) (v down) casts the ray through
//   eye + s u right - s v up,  up = right x forward,
// from 100 mm behind the plane to 100 mm beyond it.
struct ParallelCamera {
  Vec3 eye_mm, forward, right;
  double mm_per_px;
  PickRay ray(const Vec2& px) const {
    const Vec3 up = right.cross(forward);
    const Vec3 o = eye_mm + mm_per_px * px.x() * right - mm_per_px * px.y() * up;
    return {o - 100.0 * forward, o + 100.0 * forward};
  }
};

Pose pressed_pose() {
  Pose X = Pose::Identity();
  X.translation() = Vec3(1e-3, -2e-3, 4e-3);
  X.linear() = sb::Rx(0.1) * sb::Rz(0.3);
  return X;
}

TEST_CASE("the modifier held at the press picks the drag", "[drag_controller]") {
  CHECK(sb::drag_mode_for({}) == DragMode::kPlane);
  CHECK(sb::drag_mode_for({.shift = true}) == DragMode::kPush);
  CHECK(sb::drag_mode_for({.ctrl = true}) == DragMode::kTwist);
  CHECK(sb::drag_mode_for({.alt = true}) == DragMode::kTilt);
  // Shift wins over Ctrl, Ctrl over Alt.
  CHECK(sb::drag_mode_for({.shift = true, .ctrl = true, .alt = true}) == DragMode::kPush);
  CHECK(sb::drag_mode_for({.ctrl = true, .alt = true}) == DragMode::kTwist);
}

TEST_CASE("a plane drag moves the indenter with the mouse along the camera's right and up", "[drag_controller]") {
  // The iso view's direction (looking down at the pad from the front right), right horizontal. A ray moved
  // by s du along right is the same ray shifted by a horizontal vector: it meets the plane z = p.z shifted by
  // that same vector, s du right.
  const Vec3 forward = Vec3(-0.9, 1.6, -1.3).normalized();
  const Vec3 right = forward.cross(Vec3::UnitZ()).normalized();
  const double s = 0.04;  // mm per pixel
  const ParallelCamera cam{Vec3(5, -3, 20), forward, right, s};
  const Vec2 press_px(300, 200);
  const std::optional<Vec3> p_EP = sb::ray_hit_on_plane(cam.ray(press_px), 1.5);  // picked 1.5 mm above the pad
  REQUIRE(p_EP);
  DragController drag;
  drag.press(DragMode::kPlane, pressed_pose(), *p_EP, press_px);
  REQUIRE(drag.active());

  const Vec2 now_px = press_px + Vec2(10, 0);
  const Pose X = drag.pose_at(now_px, cam.ray(now_px));
  // 10 px right: 10 s mm along right, i.e. 10 s / 1000 m.
  const Vec3 expected = pressed_pose().translation() + 10 * s * right / DragController::kMmPerM;
  CHECK((X.translation() - expected).norm() < kTol);
  CHECK(X.linear().isApprox(pressed_pose().linear(), kTol));
}

TEST_CASE("from the top a plane drag moves the indenter under the mouse, z unchanged", "[drag_controller]") {
  // Looking straight down (-z) with +x to the right: screen up is +y, and pixel (u, v) lies over
  // (s u, -s v) mm. A move of (du, dv) px moves the indenter by (s du, -s dv) mm.
  const double s = 0.025;
  const ParallelCamera cam{Vec3(0, 0, 50), -Vec3::UnitZ(), Vec3::UnitX(), s};
  DragController drag;
  const Vec2 press_px(100, 80);
  drag.press(DragMode::kPlane, pressed_pose(), *sb::ray_hit_on_plane(cam.ray(press_px), 0.0), press_px);
  const Vec2 now_px(130, 60);  // 30 px right, 20 px up
  const Pose X = drag.pose_at(now_px, cam.ray(now_px));
  const Vec3 expected = pressed_pose().translation() + Vec3(s * 30, s * 20, 0) / DragController::kMmPerM;
  CHECK((X.translation() - expected).norm() < kTol);
}

TEST_CASE("a plane drag without a usable ray keeps the press pose", "[drag_controller]") {
  DragController drag;
  drag.press(DragMode::kPlane, pressed_pose(), Vec3(1, 2, 0.5), Vec2(10, 10));
  CHECK(drag.pose_at(Vec2(50, 10), std::nullopt).isApprox(pressed_pose(), kTol));
  // A ray almost parallel to the pad (a side view): its z is 4 / |(100, 0, -4)| = 0.04 of its length, under
  // kMinRaySlope.
  const PickRay grazing{Vec3(-50, 0, 2), Vec3(50, 0, -2)};
  CHECK_FALSE(sb::ray_hit_on_plane(grazing, 0.5));
  CHECK(drag.pose_at(Vec2(50, 10), grazing).isApprox(pressed_pose(), kTol));
}

TEST_CASE("a push moves the indenter along the pad normal, 0.01 mm per pixel", "[drag_controller]") {
  DragController drag;
  drag.press(DragMode::kPush, pressed_pose(), Vec3::Zero(), Vec2(200, 200));
  // 25 px down: 25 * 0.01 mm = 0.25 mm deeper (z decreases by 2.5e-4 m); sideways motion is ignored.
  const Pose X = drag.pose_at(Vec2(260, 225), std::nullopt);
  const Vec3 expected = pressed_pose().translation() - Vec3(0, 0, 25 * 0.01e-3);
  CHECK((X.translation() - expected).norm() < kTol);
  CHECK(X.linear().isApprox(pressed_pose().linear(), kTol));
  // Up pulls it out by as much.
  CHECK(drag.pose_at(Vec2(200, 175), std::nullopt).translation().z() ==
        Approx(pressed_pose().translation().z() + 25 * 0.01e-3).margin(kTol));
}

TEST_CASE("a twist of N pixels turns the indenter by N k about the pad normal", "[drag_controller]") {
  DragController drag;
  drag.press(DragMode::kTwist, pressed_pose(), Vec3::Zero(), Vec2(0, 0));
  // N = 45 px right at k = 0.4 deg/px: 18 degrees about +z, applied in E (on the left): R = Rz(18 deg) R0.
  const Pose X = drag.pose_at(Vec2(45, 7), std::nullopt);
  const double angle = 45 * 0.4 * M_PI / 180.0;
  CHECK(DragController::kTurnRadPerPx == Approx(0.4 * M_PI / 180.0));
  const sb::Mat3 turn = X.linear() * pressed_pose().linear().transpose();  // Rz(angle)
  CHECK(turn.isApprox(sb::Rz(angle), kTol));
  CHECK(std::atan2(turn(1, 0), turn(0, 0)) == Approx(angle).margin(kTol));
  CHECK((X.translation() - pressed_pose().translation()).norm() < kTol);
}

TEST_CASE("a tilt turns about y with horizontal and about x with vertical motion", "[drag_controller]") {
  DragController drag;
  drag.press(DragMode::kTilt, pressed_pose(), Vec3::Zero(), Vec2(100, 100));
  // (dx, dy) = (10, -5) px: R = Ry(10 k) Rx(-5 k) R0, k = 0.4 deg/px.
  const double k = 0.4 * M_PI / 180.0;
  const Pose X = drag.pose_at(Vec2(110, 95), std::nullopt);
  CHECK(X.linear().isApprox(sb::Ry(10 * k) * sb::Rx(-5 * k) * pressed_pose().linear(), kTol));
  CHECK((X.translation() - pressed_pose().translation()).norm() < kTol);
}

TEST_CASE("every pose is from the press, and a release ends the drag", "[drag_controller]") {
  DragController drag;
  CHECK_FALSE(drag.active());
  drag.press(DragMode::kTwist, pressed_pose(), Vec3::Zero(), Vec2(0, 0));
  const Pose once = drag.pose_at(Vec2(30, 0), std::nullopt);
  drag.pose_at(Vec2(80, 0), std::nullopt);
  CHECK(drag.pose_at(Vec2(30, 0), std::nullopt).isApprox(once, kTol));  // no accumulation between frames
  CHECK(drag.pose_at(Vec2(0, 0), std::nullopt).isApprox(pressed_pose(), kTol));
  drag.release();
  CHECK_FALSE(drag.active());
  CHECK(drag.mode() == DragMode::kNone);
}

}  // namespace test_drag_controller
