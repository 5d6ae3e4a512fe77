#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include "mini_grid.hpp"

#include "core/base/data_root.hpp"
#include "core/data/scene.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_scene {

using sbtest::kMiniMarkers;

using namespace sb;
namespace fs = std::filesystem;

namespace {
constexpr double kTol = 1e-12;  // interpolation of O(1e-2) numbers in doubles
constexpr double kAngleTol = 1e-9;

std::string data_root() {
  const char* env = std::getenv("SHEARBENCH_DATA");
  return env && *env ? env : resolve_data_root();
}
std::string scenes_dir() { return std::string(SHEARBENCH_SOURCE_DIR) + "/scenes"; }

nlohmann::json press_json() {
  return nlohmann::json::parse(R"({
    "name": "t", "motion": "dilation",
    "indenter": {"shape": "sphere", "radius_m": 0.004},
    "trajectory": {"dt_s": 0.1, "keyframes": [
      {"t_s": 0, "xyz_m": [0, 0, 0.005]},
      {"t_s": 0.25, "xyz_m": [0.001, 0, 0.0035], "rpy_deg": [0, 0, 90]}]}})");
}

// The InputError parse_scene throws for j read as "scenes/x.json" ("" when it parses).
std::string error_of(const nlohmann::json& j) {
  try {
    parse_scene(j, "scenes/x.json", data_root(), "");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST_CASE("scene: rpy_pose is extrinsic x-y-z", "[scene]") {
  // Roll 90 about x then yaw 90 about the fixed z: the I x axis stays x under the roll, then yaw takes
  // it to +y; the I y axis goes to +z under the roll and stays there under the yaw.
  const Pose X = rpy_pose(Vec3(1, 2, 3), Vec3(90, 0, 90));
  CHECK((X.linear() * Vec3::UnitX() - Vec3::UnitY()).norm() < kAngleTol);
  CHECK((X.linear() * Vec3::UnitY() - Vec3::UnitZ()).norm() < kAngleTol);
  CHECK(X.translation() == Vec3(1, 2, 3));
}

TEST_CASE("scene: trajectory sampling is linear + slerp and includes the last keyframe", "[scene]") {
  const Scene s = parse_scene(press_json(), "mem.json", data_root(), "");
  // Span 0.25 s at dt 0.1: samples at 0, 0.1, 0.2 and the last keyframe at 0.25.
  REQUIRE(s.X_EI.size() == 4);
  REQUIRE(s.t_s.size() == 4);
  CHECK(std::abs(s.t_s[2] - 0.2) < kTol);
  CHECK(s.t_s[3] == 0.25);
  // At t = 0.1, alpha = 0.4: x = 0.4 mm, z = 5 - 0.4 * 1.5 = 4.4 mm, yaw = 0.4 * 90 = 36 deg.
  CHECK(std::abs(s.X_EI[1].translation().x() - 0.0004) < kTol);
  CHECK(std::abs(s.X_EI[1].translation().z() - 0.0044) < kTol);
  const Vec3 x_axis = s.X_EI[1].linear() * Vec3::UnitX();
  CHECK(std::abs(std::atan2(x_axis.y(), x_axis.x()) - 36.0 * M_PI / 180.0) < kAngleTol);
  CHECK((s.X_EI[3].translation() - Vec3(0.001, 0, 0.0035)).norm() < kTol);
  CHECK(s.motion == "dilation");
  CHECK(s.indenter_spec.shape == "sphere");
  CHECK(s.indenter_spec.radius_m == 0.004);
  REQUIRE(s.sensor);
  CHECK(s.sensor->markers_rest_px.size() == kMiniMarkers);  // default 7 x 9
}

TEST_CASE("scene: errors name the file and the JSON pointer", "[scene]") {
  using Catch::Matchers::Contains;
  nlohmann::json j = press_json();
  j["trajectory"]["keyframes"][1]["xyz_m"] = {0, 0};
  CHECK_THAT(error_of(j), Contains("scenes/x.json: /trajectory/keyframes/1/xyz_m: expected 3 numbers"));
  j = press_json();
  j["trajectory"]["keyframes"][1]["t_s"] = 0;
  CHECK_THAT(error_of(j), Contains("/trajectory/keyframes/1/t_s: keyframe times must increase"));
  j = press_json();
  j["indenter"]["shape"] = "cube";
  CHECK_THAT(error_of(j), Contains("/indenter/shape: unknown shape 'cube'"));
  j = press_json();
  j["indenter"] = {{"shape", "mesh"}, {"mesh", "data:meshes/no_such.obj"}};
  CHECK_THAT(error_of(j), Contains("/indenter/mesh: mesh file"));
  j = press_json();
  j["trajectory"]["dt_s"] = -1;
  CHECK_THAT(error_of(j), Contains("/trajectory/dt_s: expected a positive number"));
  j = press_json();
  j["sensor"] = {{"markers", "7y9"}};
  CHECK_THAT(error_of(j), Contains("scenes/x.json"));
  j = press_json();
  j["trajektory"] = 1;
  CHECK_THAT(error_of(j), Contains("/trajektory: unknown key"));
  j = press_json();
  j.erase("trajectory");
  CHECK_THAT(error_of(j), Contains("exactly one of \"trajectory\" and \"dataset\""));
}

TEST_CASE("scene: a dataset scene replays the sample's poses", "[scene]") {
  const std::string root = data_root();
  if (!fs::exists(fs::path(root) / "twin" / "twin_sphere35"))
    FAIL("twin_sphere35 not found under " << root << " (set SHEARBENCH_DATA)");
  const nlohmann::json j = {{"dataset", {{"path", "data:twin/twin_sphere35"}, {"sample", "dil_00"}}}};
  const Scene s = parse_scene(j, "replay.json", root, "");
  REQUIRE(s.X_EI.size() == 41);
  // First row of dil_00/poses.csv.
  CHECK(s.X_EI[0].translation() == Vec3(-0.004497363, -0.000634689, 0.017700000));
  CHECK(s.motion == "dilation");
  CHECK(s.dt_s == 0.02);
  CHECK(s.indenter_spec.shape == "mesh");
  CHECK_THAT(s.indenter_spec.mesh_path, Catch::Matchers::EndsWith("sphere_r17.5.obj"));
  CHECK(s.sensor->markers_rest_px.size() == kMiniMarkers);
}

TEST_CASE("scene: every shipped scene loads", "[scene]") {
  const std::string root = data_root();
  int n = 0;
  for (const auto& entry : fs::directory_iterator(scenes_dir())) {
    if (entry.path().extension() != ".json") continue;
    INFO(entry.path());
    const Scene s = load_scene(entry.path().string(), root);
    CHECK(s.X_EI.size() >= 2);
    // Designed sphere and torus scenes: frame 0 out of contact, deepest press 0.5-1 mm. The lowest
    // point of a sphere is its centre minus r whatever the rotation; of a torus with axis a (unit, in E)
    // its centre minus R sqrt(1 - a_z^2) (the lowest point of the tube's centre circle) minus r_minor.
    const auto& spec = s.indenter_spec;
    if (s.dataset_dir.empty() && (spec.shape == "sphere" || spec.shape == "torus")) {
      auto lowest = [&](const Pose& X) {
        if (spec.shape == "sphere") return X.translation().z() - spec.radius_m;
        const double az = (X.linear() * Vec3::UnitZ()).z();
        return X.translation().z() - spec.radius_m * std::sqrt(std::max(0.0, 1 - az * az)) - spec.minor_radius_m;
      };
      double deepest = 1;
      for (const Pose& X : s.X_EI) deepest = std::min(deepest, lowest(X));
      CHECK(lowest(s.X_EI[0]) > 0);
      CHECK(-deepest >= 0.5e-3 - kTol);
      CHECK(-deepest <= 1.0e-3 + kTol);
    }
    ++n;
  }
  CHECK(n >= 10);
}

TEST_CASE("scene: a TacTip-like sensor (pinhole camera, spherical cap, pins at depth) and its errors",
          "[scene][sensor]") {
  using Catch::Matchers::Contains;
  nlohmann::json j = press_json();
  j["sensor"] = {
      {"camera",
       {{"model", "pinhole"},
        {"focal_px", 300},
        {"principal_px", {320, 240}},
        {"distance_m", 0.03},
        {"k1", -0.05},
        {"image_size_px", {640, 480}}}},
      {"gel",
       {{"surface", "spherical_cap"}, {"radius_m", 0.02}, {"footprint_radius_m", 0.0175}, {"thickness_m", 0.025}}},
      {"markers_depth_m", 0.003},
      {"markers", "5x5"}};
  const Scene scene = parse_scene(j, "scenes/x.json", data_root(), "");
  CHECK(scene.sensor->camera.pinhole());
  CHECK(scene.sensor->gel.surface == "spherical_cap");
  CHECK(scene.sensor->p_EM.size() == 25);
  CHECK(scene.sensor->p_EM[12].norm() < 1e-12);  // the centre marker: the apex over the centre pin
  CHECK_FALSE(scene.sensor->output_stage.identity());
  nlohmann::json bad = j;
  bad["sensor"]["gel"]["surface"] = "cone";
  CHECK_THAT(error_of(bad), Contains("scenes/x.json: /sensor/gel/surface"));
  bad = j;
  bad["sensor"]["gel"]["radius_m"] = 0.01;
  CHECK_THAT(error_of(bad), Contains("scenes/x.json: /sensor/gel/footprint_radius_m: must not exceed radius_m"));
  bad = j;
  bad["sensor"]["camera"]["focal_px"] = 0;
  CHECK_THAT(error_of(bad), Contains("scenes/x.json: /sensor/camera/focal_px"));
  bad = j;
  bad["sensor"]["markers_depth_m"] = "deep";
  CHECK_THAT(error_of(bad), Contains("scenes/x.json: /sensor/markers_depth_m"));
}

}  // namespace test_scene
