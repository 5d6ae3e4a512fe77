#include <catch2/catch.hpp>

#include "mini_grid.hpp"

#include "temp_path.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/base/data_root.hpp"
#include "core/data/importers.hpp"
#include "core/data/tsd.hpp"
#include "core/tracking/track_eval.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_importers {

using sbtest::kMiniMarkers;

using namespace sb;
namespace fs = std::filesystem;

namespace {

std::string require_data(const std::string& rel) {
  const char* env = std::getenv("SHEARBENCH_DATA");
  const std::string root = env && *env ? std::string(env) : resolve_data_root();
  const std::string p = fs::absolute(fs::path(root) / rel).string();
  if (!fs::exists(p)) FAIL("test data missing: " << p << " (set SHEARBENCH_DATA)");
  return p;
}

fs::path fresh_dir(const std::string& name) {
  const fs::path d = sbtest::temp_path(name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

nlohmann::json read_json(const fs::path& p) {
  std::ifstream in(p);
  REQUIRE(in);
  return nlohmann::json::parse(in);
}

// An 11 x 9 grid, pitch 27 px, with a radial field that grows linearly to A at radius a and decays as
// A a / r outside (its mean radial displacement peaks at r = a), plus a uniform drift.
struct Field {
  std::vector<Vec2> rest, disp;
};
Field radial_field(const Vec2& c, double a, double A, const Vec2& drift, const Vec2& inside_shift) {
  Field f;
  for (int r = 0; r < 9; ++r)
    for (int k = 0; k < 11; ++k) {
      const Vec2 p(25 + 27.0 * k, 12 + 27.0 * r);
      const Vec2 rv = p - c;
      const double rn = rv.norm();
      const double ur = rn < a ? A * rn / a : A * a / rn;
      f.rest.push_back(p);
      f.disp.push_back(drift + (rn > 1e-9 ? Vec2(ur * rv / rn) : Vec2(Vec2::Zero())) +
                       (rn <= a ? inside_shift : Vec2::Zero()));
    }
  return f;
}

}  // namespace

TEST_CASE("spherical-cap depth from the contact radius", "[import]") {
  // R = 3, a = 1.8: d = 3 - sqrt(9 - 3.24) = 3 - 2.4 = 0.6.
  CHECK(sphere_depth_from_contact_radius(3.0, 1.8) == Approx(0.6).epsilon(1e-12));
  CHECK(sphere_depth_from_contact_radius(3.0, 0.0) == 0.0);
  CHECK(std::isnan(sphere_depth_from_contact_radius(2.35, 2.5)));
}

TEST_CASE("the sphere contact estimate recovers centre, radius, drift and travel of a synthetic field", "[import]") {
  // Centre between markers, a = 2 pitches; the ring estimate is quantised to half a pitch (its sigma).
  constexpr double kPitch = 27, kA = 54, kCentreTolPx = 3;
  const Vec2 c(160, 120), drift(1, -2), shift(0, 0);
  const Field f = radial_field(c, kA, 6, drift, shift);
  const auto e = estimate_sphere_contact(f.rest, f.disp, kPitch);
  CHECK((e.centre_px - c).norm() < kCentreTolPx);
  CHECK(std::abs(e.a_px - kA) <= e.a_sigma_px);
  CHECK(e.a_sigma_px == Approx(kPitch / 2));
  CHECK((e.drift_px - drift).norm() < 0.5);  // the median of a field that is mostly far from the contact
  // Radial parts cancel inside a symmetric contact: travel near zero. With a shift T added inside a, travel = T.
  CHECK(e.travel_px.norm() < 1.0);
  const Vec2 T(0, 10);
  const auto es = estimate_sphere_contact_with_radius(radial_field(c, kA, 6, drift, T).rest,
                                                      radial_field(c, kA, 6, drift, T).disp, c, kA, kPitch / 2);
  CHECK((es.travel_px - T).norm() < 1.5);
}

TEST_CASE("a UV sphere OBJ is closed: V - E + F = 2", "[import]") {
  constexpr int kSlices = 12, kStacks = 6;
  std::istringstream in(sphere_obj(0.003, kSlices, kStacks));
  int v = 0, f = 0;
  std::string line;
  while (std::getline(in, line)) v += line.rfind("v ", 0) == 0, f += line.rfind("f ", 0) == 0;
  // V = slices (stacks - 1) + 2 poles; F = 2 slices (stacks - 1) triangles; E = 3F / 2.
  CHECK(v == kSlices * (kStacks - 1) + 2);
  CHECK(f == 2 * kSlices * (kStacks - 1));
  CHECK(v - 3 * f / 2 + f == 2);
}

TEST_CASE("FOTS import: two samples on the CSV grid, estimated pose, unknown-pose flag", "[import]") {
  const std::string in = require_data("raw/fots_marker_calib");
  const fs::path out = fresh_dir("sb_test_import_fots");
  import_fots(in, out.string());
  const auto j = read_json(out / "dataset.json");
  CHECK(j["format"] == "tsd/1");
  CHECK(j["sensor"]["markers_rest_px"].size() == 99);  // SOURCE.md: 11 x 9
  REQUIRE(j["samples"].size() == 2);
  for (const auto& s : j["samples"]) {
    CHECK(s["pose_known"] == false);
    CHECK(s.contains("pose_estimate"));
    CHECK(fs::exists(out / s["id"].get<std::string>() / "poses.csv"));
  }
  CHECK(fs::exists(out / "meshes" / "sphere_r3.obj"));
  const auto disp = read_markers_csv((out / "press" / "markers.csv").string(), 99);
  REQUIRE(disp.size() == 2);
  CHECK(disp[0][0].norm() == 0.0);
  CHECK(disp[1][0] == Vec2(-1, -2));  // press.csv first row: 25,11,-1,-2
  CHECK(j["provenance"].get<std::string>().find("R = 2.35 mm") != std::string::npos);
}

TEST_CASE("FEATS import: both frames kept, 7 x 9 markers tracked, none lost", "[import]") {
  const std::string in = require_data("raw/feats");
  const fs::path out = fresh_dir("sb_test_import_feats");
  import_feats(in, out.string());
  const auto j = read_json(out / "dataset.json");
  CHECK(j["sensor"]["markers_rest_px"].size() == kMiniMarkers);
  REQUIRE(j["samples"].size() == 1);
  CHECK(j["samples"][0]["has_frames"] == true);
  CHECK(fs::exists(out / "cuboid_contact" / "frames" / "000000.png"));
  CHECK(fs::exists(out / "cuboid_contact" / "frames" / "000001.png"));
  const auto disp = read_markers_csv((out / "cuboid_contact" / "markers.csv").string(), kMiniMarkers);
  REQUIRE(disp.size() == 2);
  for (int m = 0; m < kMiniMarkers; ++m) {
    CHECK(disp[0][m].norm() == 0.0);       // frame 0 is the rest
    CHECK(std::isfinite(disp[1][m].x()));  // nothing lost in the contact frame
  }
}

TEST_CASE("gsrobotics import: one dataset per video, pose unknown; an unreadable video is skipped", "[import]") {
  const std::string raw = require_data("raw/gsrobotics_tracking");
  const fs::path in = fresh_dir("sb_test_import_gs_in"), out = fresh_dir("sb_test_import_gs_out");
  fs::create_symlink(fs::path(raw) / "video_1.avi", in / "video_1.avi");  // 10 frames, 8 x 10 markers
  fs::create_symlink(fs::path(raw) / "video_4.avi", in / "video_4.avi");  // no decodable frame
  const ImportReport rep = import_gsrobotics(in.string(), out.string(), TrackerOptions{}, 0.0634);
  REQUIRE(rep.datasets.size() == 1);
  CHECK(rep.lines.size() == 2);
  const auto j = read_json(out / "video_1" / "dataset.json");
  CHECK(j["sensor"]["markers_rest_px"].size() == 80);
  CHECK(j["sensor"]["camera"]["mm_per_px"] == 0.0634);
  CHECK(j["samples"][0]["motion"] == "free");
  CHECK(j["samples"][0]["pose_known"] == false);
  CHECK(j["samples"][0]["dt_s"].get<double>() == Approx(0.04));
  const auto disp = read_markers_csv((out / "video_1" / "gsrobotics_video_1" / "markers.csv").string(), 80);
  CHECK(disp.size() == 10);
}

TEST_CASE("incipient-slip import keeps the slip label", "[import]") {
  const std::string raw = require_data("raw/incipient_slip/plier_exp1");
  const fs::path in = fresh_dir("sb_test_import_slip_in"), out = fresh_dir("sb_test_import_slip_out");
  fs::create_directories(in / "plier_exp1");
  fs::create_symlink(fs::path(raw) / "camera_2.avi", in / "plier_exp1" / "camera_2.avi");
  std::ofstream(in / "plier_exp1" / "slip.txt");
  fs::create_directories(in / "nolabel_exp1");
  fs::create_symlink(fs::path(raw) / "camera_2.avi", in / "nolabel_exp1" / "camera_2.avi");
  const ImportReport rep = import_incipient_slip(in.string(), out.string(), TrackerOptions{}, 0.0634);
  REQUIRE(rep.datasets.size() == 2);
  CHECK(read_json(out / "plier_exp1_camera_2" / "dataset.json")["samples"][0]["slip_label"] == true);
  CHECK(read_json(out / "nolabel_exp1_camera_2" / "dataset.json")["samples"][0]["slip_label"] == false);
}

TEST_CASE("imported datasets pass the tsd/1 reader", "[import]") {
  // The data helper's reader validates dataset.json (indenters with meshes, samples) and the CSVs.
  const fs::path out = fresh_dir("sb_test_import_readback");
  import_fots(require_data("raw/fots_marker_calib"), (out / "fots").string());
  import_feats(require_data("raw/feats"), (out / "feats").string());
  for (const char* name : {"fots", "feats"}) {
    INFO(name);
    const Dataset ds = read_dataset((out / name).string());
    for (const auto& s : ds.samples) {
      const SampleData d = read_sample(ds, s.id);
      CHECK_FALSE(s.pose_known);
      CHECK(d.markers_px.size() == 2);
    }
  }
}

}  // namespace test_importers
