// The GelSight Mini sensor: marker grid, camera mapping, flat default sensor, and the real domed gel in E.
#include <catch2/catch.hpp>

#include "mini_grid.hpp"

#include <cstdlib>
#include <filesystem>

#include "core/base/data_root.hpp"
#include "core/sensor/sensor.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_sensor_tests {  // not test_sensor: the fixtures (model_fixtures.hpp) have a function of that name

using sbtest::kMiniMarkers;

using sb::Vec2;
using sb::Vec3;

namespace {
constexpr double mm = 1e-3;
std::string gel_obj_path() {
  const char* env = std::getenv("SHEARBENCH_DATA");
  return (env ? std::string(env) : sb::resolve_data_root()) + "/meshes/gel_gelsight_mini.obj";
}
}  // namespace

TEST_CASE("marker grid 7x9 at 33 px is centred on the principal point, x fastest", "[sensor]") {
  // u = 159.5 + (c - 4) * 33, v = 119.5 + (r - 3) * 33: first (27.5, 20.5), last (291.5, 218.5).
  const sb::Camera camera;
  const auto uv = sb::marker_grid_px(sb::MarkerGrid{}, camera);
  REQUIRE(uv.size() == kMiniMarkers);
  CHECK(uv.front() == Vec2(27.5, 20.5));
  CHECK(uv[1] == Vec2(60.5, 20.5));     // next column: x fastest
  CHECK(uv[9] == Vec2(27.5, 53.5));     // second row
  CHECK(uv[31] == Vec2(159.5, 119.5));  // centre marker (r 3, c 4) on the principal point
  CHECK(uv.back() == Vec2(291.5, 218.5));
}

TEST_CASE("parse_marker_grid reads ROWSxCOLS and rejects anything else", "[sensor]") {
  const sb::MarkerGrid g = sb::parse_marker_grid("7x9", "scene.json:3:14");
  CHECK(g.rows == 7);
  CHECK(g.cols == 9);
  CHECK(sb::parse_marker_grid("11X13", "x").cols == 13);
  CHECK_THROWS_AS(sb::parse_marker_grid("7x", "scene.json:3:14"), sb::InputError);
  CHECK_THROWS_AS(sb::parse_marker_grid("0x9", "scene.json:3:14"), sb::InputError);
  CHECK_THROWS_AS(sb::parse_marker_grid("7*9", "scene.json:3:14"), sb::InputError);
  try {
    sb::parse_marker_grid("seven", "scene.json:3:14");
  } catch (const sb::InputError& e) {
    CHECK(std::string(e.what()).find("scene.json:3:14") != std::string::npos);
  }
}

TEST_CASE("camera px -> E -> px round trip is exact", "[sensor]") {
  const sb::Camera camera;
  constexpr double kRoundTripPx = 1e-9;
  for (const Vec2& uv : {Vec2(0, 0), Vec2(27.5, 20.5), Vec2(319.9, 239.9), Vec2(159.5, 119.5)}) {
    CHECK((camera.px_from_E(camera.E_from_px(uv)) - uv).norm() < kRoundTripPx);
  }
  // 33 px at 0.0634 mm/px = 2.0922 mm.
  CHECK(camera.E_displacement(Vec2(33, 0)).x() == Approx(2.0922 * mm).epsilon(1e-12));
}

TEST_CASE("default sensor: flat pad, markers on z = 0", "[sensor]") {
  const sb::Sensor s = sb::make_default_sensor();
  REQUIRE(s.p_EM.size() == kMiniMarkers);
  // First marker: ((27.5 - 159.5), (20.5 - 119.5)) px * 0.0634e-3 m/px = (-8.3688, -6.2766) mm.
  CHECK(s.p_EM.front().x() == Approx(-8.3688 * mm).epsilon(1e-12));
  CHECK(s.p_EM.front().y() == Approx(-6.2766 * mm).epsilon(1e-12));
  CHECK(s.p_EM.front().z() == 0.0);
  // Pad SDF: 1 mm under the centre of the surface is 1 mm deep; the pad is 4.5 mm thick.
  CHECK(s.gel_sdf->value(Vec3(0, 0, -1 * mm)) == Approx(-1 * mm));
  CHECK(s.gel_sdf->value(Vec3(0, 0, -5.5 * mm)) == Approx(1 * mm));
  const auto b = s.gel_mesh.bounds();
  CHECK(b.max().z() == Approx(0).margin(1e-15));
  CHECK(b.min().z() == Approx(-4.5 * mm));
  CHECK(b.sizes().x() == Approx(25.25 * mm));
  CHECK(b.sizes().y() == Approx(20.75 * mm));
  CHECK(s.gel_mesh.signed_volume() == Approx(25.25 * 20.75 * 4.5 * mm * mm * mm));
}

TEST_CASE("GelSight Mini gel mesh placed in E: apex at z = 0, domed top, right size", "[sensor]") {
  const std::string path = gel_obj_path();
  INFO("needs " << path);
  REQUIRE(std::filesystem::exists(path));
  const sb::TriMesh gel = sb::gelsight_mini_gel_in_E(path);
  const auto b = gel.bounds();
  // SOURCE.md: x 25.25 mm, CAD z (-> E y) 20.75 mm, thin axis 4.0 mm; outward normals kept (volume > 0).
  constexpr double kCadTolerance = 0.01 * mm;
  CHECK(b.max().z() == Approx(0).margin(1e-12));
  CHECK(b.sizes().x() == Approx(25.25 * mm).margin(kCadTolerance));
  CHECK(b.sizes().y() == Approx(20.75 * mm).margin(kCadTolerance));
  CHECK(b.sizes().z() == Approx(4.0 * mm).margin(kCadTolerance));
  CHECK(b.center().head<2>().norm() < kCadTolerance);
  CHECK(gel.signed_volume() > 0);
  // Thickness: 4.0 mm at the centre; about 3.5 mm 1 mm in from a long edge (y = +-(10.375 - 1) mm).
  const auto centre = sb::vertical_span(gel, Vec2(0, 0));
  REQUIRE(centre);
  CHECK(centre->z_high == Approx(0).margin(kCadTolerance));
  CHECK(centre->z_high - centre->z_low == Approx(4.0 * mm).margin(kCadTolerance));
  for (double y : {-9.375 * mm, 9.375 * mm}) {
    const auto edge = sb::vertical_span(gel, Vec2(0, y));
    REQUIRE(edge);
    const double thickness = edge->z_high - edge->z_low;
    WARN("gel thickness 1 mm in from the long edge: " << thickness / mm << " mm");
    CHECK(thickness > 2.75 * mm);
    CHECK(thickness < 3.6 * mm);
  }
  // The dome: the surface falls monotonically from the centre towards the long edge.
  CHECK(sb::vertical_span(gel, Vec2(0, 5 * mm))->z_high < 0);
  CHECK(sb::vertical_span(gel, Vec2(0, 9 * mm))->z_high < sb::vertical_span(gel, Vec2(0, 5 * mm))->z_high);
  // The bottom is flat at z = -4 mm.
  CHECK(sb::vertical_span(gel, Vec2(8 * mm, 6 * mm))->z_low == Approx(-4.0 * mm).margin(kCadTolerance));
}

TEST_CASE("sensor with the mesh gel: markers on the domed surface, mesh SDF", "[sensor][slow]") {
  const std::string path = gel_obj_path();
  INFO("needs " << path);
  REQUIRE(std::filesystem::exists(path));
  const sb::TriMesh gel_E = sb::gelsight_mini_gel_in_E(path);
  const sb::Camera camera;
  sb::GelSpec spec;
  spec.surface = path;
  const sb::Sensor s = sb::make_sensor(camera, spec, sb::marker_grid_px(sb::MarkerGrid{}, camera), &gel_E);
  REQUIRE(s.p_EM.size() == kMiniMarkers);
  CHECK(s.gel.thickness_m == Approx(4.0 * mm).margin(0.01 * mm));
  // Centre marker sits on the apex; corner markers lower on the dome.
  CHECK(s.p_EM[31].z() == Approx(0).margin(1e-9));
  CHECK(s.p_EM.front().z() < 0);
  // The mesh SDF vanishes on the markers (within a tenth of a voxel, voxel = 0.165 mm here) and is 1 mm deep
  // 1 mm under the apex (the bottom is 3 mm away; at 2 mm depth both faces are equidistant, a crease).
  const double kOnSurface = 0.02 * mm;
  for (const Vec3& p : s.p_EM) CHECK(std::abs(s.gel_sdf->value(p)) < kOnSurface);
  CHECK(s.gel_sdf->value(Vec3(0, 0, -1 * mm)) == Approx(-1 * mm).margin(kOnSurface));
  CHECK_THROWS_AS(sb::make_sensor(camera, spec, {Vec2(-200, 0)}, &gel_E), sb::InputError);
  CHECK_THROWS_AS(sb::make_sensor(camera, spec, {}), std::invalid_argument);
}

}  // namespace test_sensor_tests
