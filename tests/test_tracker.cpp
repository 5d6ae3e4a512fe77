#include <catch2/catch.hpp>

#include "mini_grid.hpp"

#include "temp_path.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "core/base/data_root.hpp"
#include "core/base/error.hpp"
#include "core/tracking/track_eval.hpp"
#include "core/tracking/tracker.hpp"
#include "marker_render.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_tracker {

using sbtest::kMiniMarkers;

using namespace sb;
using sb::test::grid_7x9;
using sb::test::nearest;
using sb::test::render;
namespace fs = std::filesystem;

namespace {

std::string data_root() {
  const char* env = std::getenv("SHEARBENCH_DATA");
  return env && *env ? std::string(env) : resolve_data_root();
}

std::string require_data(const std::string& rel) {
  const std::string p = (fs::path(data_root()) / rel).string();
  if (!fs::exists(p)) FAIL("test data missing: " << p << " (set SHEARBENCH_DATA)");
  return p;
}

}  // namespace

TEST_CASE("twin_frames: tracked displacement fields match the exact ones", "[tracker]") {
  // Requirement: RMSE <= 0.15 px against markers.csv and no marker lost (measured: about 0.012 px).
  constexpr double kMaxRmsePx = 0.15;
  const std::string root = require_data("twin/twin_frames");
  std::ifstream in(fs::path(root) / "dataset.json");
  const auto j = nlohmann::json::parse(in);
  std::vector<Vec2> rest;
  for (const auto& p : j["sensor"]["markers_rest_px"]) rest.emplace_back(p[0].get<double>(), p[1].get<double>());
  for (const char* sample : {"dil_00", "shr_00", "twi_01"}) {
    INFO(sample);
    const fs::path dir = fs::path(root) / sample;
    const TrackResult r = track_frames_dir((dir / "frames").string(), TrackerOptions{});
    const auto ref = read_markers_csv((dir / "markers.csv").string(), int(rest.size()));
    REQUIRE(r.frames() == int(ref.size()));
    CHECK(r.grid_rows == 7);
    CHECK(r.grid_cols == 9);
    const TrackComparison c = compare_to_reference(r, rest, ref, false);
    CHECK(c.paired_markers == kMiniMarkers);
    CHECK(c.lost == 0);
    CHECK(c.pairs == kMiniMarkers * r.frames());
    CHECK(c.rmse_px <= kMaxRmsePx);
    CHECK(r.lost_fraction() == 0.0);
  }
}

TEST_CASE("a 30 px shear ramp, strong in the middle and weak at the edge, is tracked without a swap", "[tracker]") {
  // du(p, t) = 30 px * min(t/6, 1) * exp(-|p - c|^2 / (2 * 60^2)): 5 px per frame at the centre, so
  // neighbours 33 px apart end up to ~20 px out of step; a swap would show as an error of about a pitch.
  constexpr double kPeakPx = 30, kWidthPx = 60, kMaxErrorPx = 0.3;
  const Vec2 centre(159.5, 119.5);
  const auto rest = grid_7x9();
  auto field = [&](const Vec2& p, int t) {
    const double s = std::min(1.0, t / 6.0);
    return Vec2(kPeakPx * s * std::exp(-(p - centre).squaredNorm() / (2 * kWidthPx * kWidthPx)), 0.0);
  };
  std::mt19937 rng(7);
  std::vector<cv::Mat> frames;
  constexpr int kFrames = 10;
  for (int t = 0; t < kFrames; ++t) {
    std::vector<Vec2> c;
    for (const auto& p : rest) c.push_back(p + field(p, t));
    frames.push_back(render(c, rng));
  }
  TrackerOptions opts;
  opts.rest_frames = 1;
  const TrackResult r = track_frames(frames, opts);
  REQUIRE(r.markers() == kMiniMarkers);
  double worst = 0;
  for (const auto& p : rest) {
    const int m = nearest(r, p);
    for (int t = 0; t < kFrames; ++t) {
      const Vec2 d = r.disp_px[t][m];
      REQUIRE(std::isfinite(d.x()));
      worst = std::max(worst, (d - field(p, t)).norm());
    }
  }
  CHECK(worst < kMaxErrorPx);
  // The centre marker really moved 30 px (not a trivially small field).
  CHECK(r.disp_px[kFrames - 1][nearest(r, Vec2(159.5, 119.5))].x() == Approx(30 * std::exp(0.0)).margin(kMaxErrorPx));
}

TEST_CASE("a dot that leaves the image is lost, the others are unaffected, and it is re-acquired", "[tracker]") {
  // Uniform shift du = 4 px per frame for 8 frames (to 32 px), then back. The right column (rest u = 291.5)
  // reaches u = 323.5 > 320 + r: gone; the column left of it (258.5) stays inside.
  constexpr double kStepPx = 4, kMaxErrorPx = 0.3;
  const auto rest = grid_7x9();
  std::vector<double> shift;
  for (int t = 0; t <= 8; ++t) shift.push_back(kStepPx * t);
  for (int t = 7; t >= 0; --t) shift.push_back(kStepPx * t);
  std::mt19937 rng(3);
  std::vector<cv::Mat> frames;
  for (double s : shift) {
    std::vector<Vec2> c;
    for (const auto& p : rest) c.push_back(p + Vec2(s, 0));
    frames.push_back(render(c, rng));
  }
  TrackerOptions opts;
  opts.rest_frames = 1;
  const TrackResult r = track_frames(frames, opts);
  REQUIRE(r.markers() == kMiniMarkers);
  for (std::size_t t = 0; t < shift.size(); ++t) {
    for (const auto& p : rest) {
      const Vec2 d = r.disp_px[t][nearest(r, p)];
      const double u = p.x() + shift[t];
      if (u - 5 > 320) {
        CHECK_FALSE(std::isfinite(d.x()));  // fully outside: lost, never given to another dot
      } else if (u + 5 < 319) {
        REQUIRE(std::isfinite(d.x()));
        CHECK((d - Vec2(shift[t], 0)).norm() < kMaxErrorPx);
      }
    }
  }
  // Back at rest at the end: every marker, the right column included, is tracked again.
  for (const auto& d : r.disp_px.back()) {
    REQUIRE(std::isfinite(d.x()));
    CHECK(d.norm() < kMaxErrorPx);
  }
}

TEST_CASE("an unreadable video gives an InputError naming it", "[tracker]") {
  const fs::path dir = sbtest::temp_path("sb_test_tracker_badvideo");
  fs::create_directories(dir);
  const std::string bad = (dir / "not_a_video.avi").string();
  std::ofstream(bad) << "this is text, not a video\n";
  try {
    track_video(bad, TrackerOptions{});
    FAIL("no exception");
  } catch (const InputError& e) {
    CHECK(e.file() == bad);
  }
  CHECK_THROWS_AS(track_video((dir / "missing.avi").string(), TrackerOptions{}), InputError);
  CHECK_THROWS_AS(track_frames_dir((dir / "no_such_dir").string(), TrackerOptions{}), InputError);
  fs::remove_all(dir);
}

TEST_CASE("grid specifications parse or are rejected with the flag named", "[tracker]") {
  TrackerOptions o;
  parse_grid("11x9", "--grid", o);
  CHECK(o.grid_rows == 11);
  CHECK(o.grid_cols == 9);
  parse_grid("auto", "--grid", o);
  CHECK(o.grid_rows == 0);
  CHECK_THROWS_WITH(parse_grid("7by9", "--grid", o), Catch::Contains("--grid"));
  CHECK_THROWS_AS(parse_grid("1x9", "--grid", o), InputError);
}

TEST_CASE("the vendor tracker CSV is read as frames x (row, col)", "[tracker]") {
  const std::string csv = require_data("raw/gsrobotics_tracking/marker_locations_1.csv");
  const VendorTrack v = read_vendor_csv(csv);
  // SOURCE.md: 8 x 10 grid; video_1 has 10 frames; the first row is "1, 0, 0, 12.16, 4.74, 12.16, 4.74".
  CHECK(v.frames == 10);
  REQUIRE(v.rest_px.size() == 80);
  CHECK(v.rest_px[0].x() == Approx(12.16));
  CHECK(v.position_px[0][0].y() == Approx(4.74));
}

}  // namespace test_tracker
