// Sensors that are not the GelSight Mini: the pinhole camera (projection, Jacobian, back-projection), the
// spherical-cap skin (TacTip) with pins at depth, and the output stage every model's field goes through.
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>

#include "core/base/error.hpp"
#include "core/models/model.hpp"
#include "core/sensor/output_stage.hpp"
#include "core/sensor/sensor.hpp"
#include "model_fixtures.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_sensor_models {

using sb::Camera;
using sb::CameraModel;
using sb::GelSpec;
using sb::Sensor;
using sb::Vec2;
using sb::Vec3;

namespace {

constexpr double kExactPx = 1e-9;       // px: values exact in binary, up to a few roundings
constexpr double kExactMetres = 1e-12;  // m: a round trip through the camera and the sphere

// f = 500 px, principal point (320, 240), camera D = 50 mm below the apex.
Camera pinhole_camera(double k1) {
  Camera c;
  c.model = CameraModel::kPinhole;
  c.focal_px = 500.0;
  c.principal_px = Vec2(320.0, 240.0);
  c.width_px = 640;
  c.height_px = 480;
  c.distance_m = 0.05;
  c.k1 = k1;
  return c;
}

GelSpec cap(double radius, double footprint, double thickness, double depth) {
  GelSpec g;
  g.surface = "spherical_cap";
  g.radius_m = radius;
  g.footprint_radius_m = footprint;
  g.thickness_m = thickness;
  g.markers_depth_m = depth;
  return g;
}

}  // namespace

TEST_CASE("pinhole camera: projection and its Jacobian by hand", "[sensor][camera]") {
  const Camera c = pinhole_camera(0.1);
  // p = (10, -5, -10) mm: w = z + D = 0.04, n = (x, y) / w = (0.25, -0.125), r^2 = 0.078125,
  // 1 + k1 r^2 = 1.0078125; u = 320 + 500 * 1.0078125 * 0.25 = 445.9765625, v = 240 - 62.98828125.
  const Vec3 p(0.01, -0.005, -0.01);
  const Vec2 uv = c.project(p);
  CHECK(uv.x() == Approx(445.9765625).margin(kExactPx));
  CHECK(uv.y() == Approx(177.01171875).margin(kExactPx));
  // dn/dp = [1/w, 0, -nx/w; 0, 1/w, -ny/w] = [25, 0, -6.25; 0, 25, 3.125];
  // dg/dn = 1.0078125 I + 2 k1 n n^T = [1.0203125, -0.00625; -0.00625, 1.0109375];
  // J = 500 dg/dn dn/dp = [12753.90625, -78.125, -3198.2421875; -78.125, 12636.71875, 1599.12109375].
  const auto J = c.project_jacobian(p);
  const double expected[2][3] = {{12753.90625, -78.125, -3198.2421875}, {-78.125, 12636.71875, 1599.12109375}};
  for (int r = 0; r < 2; ++r)
    for (int k = 0; k < 3; ++k) CHECK(J(r, k) == Approx(expected[r][k]).margin(kExactPx * 1e3));
  // The orthographic camera: J = [1/s, 0, 0; 0, 1/s, 0], the same numbers px_from_E uses.
  const Camera mini;
  const auto Jo = mini.project_jacobian(p);
  CHECK(Jo(0, 0) == mini.px_per_metre());
  CHECK(Jo(1, 1) == mini.px_per_metre());
  CHECK(Jo(0, 2) == 0.0);
  CHECK(mini.project(p) == mini.px_from_E(p.head<2>()));
}

TEST_CASE("pinhole camera: back-projection inverts the distortion", "[sensor][camera]") {
  const Camera c = pinhole_camera(-0.2);  // barrel distortion, as a wide-angle TacTip lens has
  for (const Vec2& uv : {Vec2(320, 240), Vec2(600, 100), Vec2(10, 470), Vec2(321, 239)}) {
    const auto ray = c.back_project(uv);
    REQUIRE(ray);
    CHECK(ray->origin_E == Vec3(0, 0, -c.distance_m));
    for (double t : {0.01, 0.05}) {
      const Vec2 back = c.project(ray->origin_E + t * ray->direction_E);
      CHECK((back - uv).norm() < kExactPx);
    }
  }
  // Beyond the fold of r (1 + k1 r^2) (r = 1 / sqrt(-3 k1) = 1.29, r_d = 0.86) no point projects there.
  CHECK_FALSE(c.back_project(Vec2(320 + 500 * 0.9, 240)));
}

TEST_CASE("spherical cap with a pinhole camera: pins on the sphere R - depth, back-projected", "[sensor][camera]") {
  const GelSpec gel = cap(0.025, 0.02, 0.015, 0.005);
  const Camera cam = pinhole_camera(0.05);
  const std::vector<Vec2> markers = {{320, 240}, {470, 240}, {200, 400}, {420, 130}};
  const Sensor s = sb::make_sensor(cam, gel, markers);
  REQUIRE(s.p_EM.size() == markers.size());
  // p_EM is the surface point over each pin (radius R about the centre c); the pin c + (p_EM - c) r_p / R.
  const Vec3 c_E(0, 0, -0.025);
  for (std::size_t i = 0; i < markers.size(); ++i) {
    CHECK((s.p_EM[i] - c_E).norm() == Approx(0.025).margin(kExactMetres));
    const Vec3 pin = c_E + (s.p_EM[i] - c_E) * (0.020 / 0.025);
    CHECK((cam.project(pin) - markers[i]).norm() < kExactPx);
    CHECK(s.p_EM[i].z() > -0.025);  // the upper crossing
  }
  CHECK(s.p_EM[0].norm() < 1e-15);
  CHECK(s.gel.size_m.x() == Approx(0.04).margin(1e-12));
  CHECK(s.gel.thickness_m == Approx(0.015).margin(1e-12));
  // A marker whose ray meets the pin sphere below the cap's rim is rejected, naming it.
  try {
    sb::make_sensor(pinhole_camera(0.0), cap(0.025, 0.01, 0.015, 0.005), {{620, 240}});
    FAIL("expected an InputError");
  } catch (const sb::InputError& e) {
    CHECK_THAT(e.what(), Catch::Contains("(620, 240) px") && Catch::Contains("footprint"));
  }
}

TEST_CASE("spherical cap mesh: closed, outward, and a flat press gives the contact radius sqrt(2 R d - d^2)",
          "[sensor][cap]") {
  const double R = 0.02;
  const GelSpec gel = cap(R, 0.015, 0.02, 0.0);
  const sb::TriMesh mesh = sb::spherical_cap_mesh(gel);
  const sb::MeshReport report = sb::validate_mesh(mesh);
  CHECK(report.closed());
  CHECK(mesh.signed_volume() > 0.0);
  const Sensor s = sb::make_sensor(Camera{}, gel, {Vec2(159.5, 119.5)});
  CHECK(s.p_EM[0].norm() < 1e-15);  // the apex marker sits at the apex
  // A flat indenter face at z = -d cuts the sphere |p - (0, 0, -R)| = R in the circle
  // x^2 + y^2 = R^2 - (R - d)^2 = 2 R d - d^2; its contact is where phi_E < 0 on that plane. Bisection of phi
  // along rays in three directions gives the edge.
  // Tolerance: the mesh field is trilinear on voxels of ~0.23 mm (bbox diagonal / 200) and the plane meets the
  // surface at the polar angle theta (sin theta = a / R), so a field error e moves the edge by e / sin(theta);
  // measured worst error 0.012 mm (d = 0.5 mm).
  constexpr double kContactRadiusTolerance = 0.03e-3;
  double previous = 0.0;
  for (double d : {0.5e-3, 1e-3, 2e-3, 4e-3}) {
    const double expected = std::sqrt(2 * R * d - d * d);
    for (double angle : {0.0, 2.0, 4.2}) {
      const Vec2 dir(std::cos(angle), std::sin(angle));
      double inside = 0.0, outside = 0.015;
      for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (inside + outside);
        (s.gel_sdf->value(Vec3(mid * dir.x(), mid * dir.y(), -d)) < 0.0 ? inside : outside) = mid;
      }
      INFO("d = " << d << " angle " << angle);
      CHECK(inside == Approx(expected).margin(kContactRadiusTolerance));
      CHECK(inside > previous);  // the contact grows with the press
    }
    previous = expected;
  }
}

TEST_CASE("output stage: the identity for the GelSight Mini, bit for bit", "[sensor][output_stage]") {
  const Sensor mini = sb::make_default_sensor();
  CHECK(mini.output_stage.identity());
  std::vector<Vec2> field;
  for (std::size_t i = 0; i < mini.p_EM.size(); ++i) field.emplace_back(0.1 * i + 1.0 / 3.0, -0.7 * i);
  const auto before = field;
  mini.output_stage.apply(field);
  CHECK(field == before);
  // The orthographic camera with markers at depth: only the smoothing, no perspective map.
  GelSpec deep;
  deep.markers_depth_m = 1e-3;
  const Sensor d = sb::make_sensor(Camera{}, deep, mini.markers_rest_px);
  CHECK_FALSE(d.output_stage.identity());
  CHECK(d.output_stage.perspective_maps().empty());
  CHECK(d.p_EM[0].z() == 0.0);  // the models see the surface point over the pin
}

TEST_CASE("output stage: depth smoothing then the perspective map, by hand for two pins on a dome",
          "[sensor][output_stage]") {
  // Dome R = 25 mm, pins d = 5 mm deep (pin sphere r_p = 20 mm about (0, 0, -25) mm), camera f = 500 px,
  // D = 49 mm, no distortion. Pin B at (12, 0, -9) mm (12^2 + 16^2 = 20^2) has w = z + D = 40 mm and is
  // seen at u = 320 + 500 * 12 / 40 = 470. Pin A at the pin apex (0, 0, -5) mm, seen at the principal point.
  Camera cam = pinhole_camera(0.0);
  cam.distance_m = 0.049;
  const Sensor s = sb::make_sensor(cam, cap(0.025, 0.02, 0.015, 0.005), {{320, 240}, {470, 240}});
  // The models see pin B at the surface point over it: c + (12, 0, 16) mm * 25 / 20 = (15, 0, -5) mm.
  REQUIRE(s.p_EM[1].isApprox(Vec3(0.015, 0, -0.005), 1e-12));
  // (a) Smoothing, sigma = d: the pins are 12 mm apart in xy, e = exp(-12^2 / (2 * 5^2)) = exp(-2.88); rows
  //     normalised: A' = (d_A + e d_B) / (1 + e), B' = (e d_A + d_B) / (1 + e).
  // (b) With k1 = 0, J = f / w [I, -p_xy / w], s_0 = f / (D - d), and T the pole's tangent plane rotated onto
  //     the pin's: pin B's normal is n = (12, 0, 16) / 20 = (0.6, 0, 0.8), a rotation about y by the polar angle
  //     (sin 0.6, cos 0.8), so T = [(0.8, 0, -0.6), (0, 1, 0)]. Pin A: A = I. Pin B along x:
  //     ((D - d) / w) (0.8 + (12 / 40) 0.6) = 1.1 * 0.98 = 1.078; along y: 1.1.
  std::vector<Vec2> field = {Vec2(0, 0), Vec2(1, 1)};
  s.output_stage.apply(field);
  const double e = std::exp(-2.88);
  constexpr double kHand = 1e-12;
  CHECK(field[0].x() == Approx(e / (1 + e)).margin(kHand));
  CHECK(field[0].y() == Approx(e / (1 + e)).margin(kHand));
  CHECK(field[1].x() == Approx(1.078 / (1 + e)).margin(kHand));
  CHECK(field[1].y() == Approx(1.1 / (1 + e)).margin(kHand));
}

TEST_CASE("output stage: an in-plane displacement is carried onto the pin sphere with its length kept",
          "[sensor][output_stage]") {
  // Sphere about c = (0, 0, -25) mm of radius 20 mm. At the pole n = ez: T = [ex, ey]. At the equator point
  // (20, 0, -25) mm, n = ex: the rotation about y by 90 deg takes ex to -ez and keeps ey, so a radial
  // displacement runs down the sphere with its length, never the unbounded lift dz = -x dx / (z - c_z).
  constexpr double kRotation = 1e-12;
  const double c_z = -0.025;
  const auto pole = sb::tangent_frame_on_sphere(Vec3(0, 0, -0.005), c_z);
  CHECK(pole.col(0).isApprox(Vec3::UnitX(), kRotation));
  CHECK(pole.col(1).isApprox(Vec3::UnitY(), kRotation));
  const auto equator = sb::tangent_frame_on_sphere(Vec3(0.02, 0, c_z), c_z);
  CHECK((equator.col(0) - Vec3(0, 0, -1)).norm() < kRotation);
  CHECK((equator.col(1) - Vec3(0, 1, 0)).norm() < kRotation);
  // Anywhere: orthonormal columns, both tangent to the sphere.
  const Vec3 p(0.011, -0.013, -0.025 + std::sqrt(0.02 * 0.02 - 0.011 * 0.011 - 0.013 * 0.013));
  const auto T = sb::tangent_frame_on_sphere(p, c_z);
  const Vec3 n = (p - Vec3(0, 0, c_z)).normalized();
  CHECK((T.transpose() * T - Eigen::Matrix2d::Identity()).norm() < kRotation);
  CHECK(std::abs(T.col(0).dot(n)) < kRotation);
  CHECK(std::abs(T.col(1).dot(n)) < kRotation);
}

TEST_CASE("every model's field goes through the sensor's output stage", "[sensor][output_stage][models]") {
  // The same sensor with and without its stage: the model output differs exactly by the stage.
  Camera cam = pinhole_camera(-0.05);
  std::vector<Vec2> markers;
  for (int r = -2; r <= 2; ++r)
    for (int c = -2; c <= 2; ++c) markers.emplace_back(320 + 40.0 * c, 240 + 40.0 * r);
  auto staged = std::make_shared<const Sensor>(sb::make_sensor(cam, cap(0.02, 0.018, 0.015, 0.002), markers));
  REQUIRE_FALSE(staged->output_stage.identity());
  auto plain_copy = std::make_shared<Sensor>(*staged);
  plain_copy->output_stage = sb::SensorOutputStage{};
  std::shared_ptr<const Sensor> plain = plain_copy;
  const auto ind = sbtest::sphere_indenter(0.006);
  // Pressed 1 mm into the apex, then slid 0.5 mm along x (a shear field; a pure press moves no marker).
  sb::Pose pressed = sb::Pose::Identity();
  pressed.translation() = Vec3(0.0, 0.0, 0.006 - 0.001);
  sb::Pose slid = pressed;
  slid.translation().x() = 0.0005;
  for (const std::string id : {"tacsl", "fots"}) {
    auto a = sb::make_model(id, staged, ind);
    auto b = sb::make_model(id, plain, ind);
    sb::FieldOutput fa, fb;
    for (const sb::Pose& X_EI : {pressed, slid}) {
      a->step(X_EI, 0.01, &fa);
      b->step(X_EI, 0.01, &fb);
    }
    staged->output_stage.apply(fb.disp_px);
    INFO(id);
    REQUIRE(fa.disp_px.size() == fb.disp_px.size());
    double moved = 0.0;
    for (std::size_t i = 0; i < fa.disp_px.size(); ++i) {
      CHECK(fa.disp_px[i] == fb.disp_px[i]);
      moved += fa.disp_px[i].norm();
    }
    CHECK(moved > 0.0);
  }
}

}  // namespace test_sensor_models
