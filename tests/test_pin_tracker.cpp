// The TacTip pin tracker (core/tracking/pin_tracker) on the real reference image, and the tactip_shear
// importer on a few samples of ../shared/data/raw/tactip_shear (imported into a temporary folder).
#include <catch2/catch.hpp>

#include "temp_path.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/base/data_root.hpp"
#include "core/base/error.hpp"
#include "core/calibration/fit_data.hpp"
#include "core/data/importers.hpp"
#include "core/data/tsd.hpp"
#include "core/tracking/pin_tracker.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_pin_tracker {

using namespace sb;
namespace fs = std::filesystem;

namespace {

std::string tactip_data(const std::string& rel) {
  const char* env = std::getenv("SHEARBENCH_DATA");
  const std::string root = env && *env ? std::string(env) : resolve_data_root();
  const std::string p = fs::absolute(fs::path(root) / "raw/tactip_shear" / rel).string();
  if (!fs::exists(p)) FAIL("test data missing: " << p << " (set SHEARBENCH_DATA)");
  return p;
}

cv::Mat grey(const std::string& path) {
  cv::Mat m = cv::imread(path, cv::IMREAD_GRAYSCALE);
  REQUIRE(!m.empty());
  return m;
}

int kept(const std::vector<Vec2>& disp) {
  int n = 0;
  for (const auto& d : disp) n += d.allFinite();
  return n;
}

}  // namespace

TEST_CASE("TacTip reference: every pin found, a hand-checked pin centre", "[tracker][tactip]") {
  const std::string path = tactip_data("calibration/images/image_0.png");
  const PinReference ref = make_pin_reference(grey(path), PinTrackerOptions{}, path);
  // SOURCE.md: "about 330 pins" by inspection; the detector finds 327 whole pins (the ragged blobs at the
  // mask edge are rejected by the fill / area tests). A change of the count is a change of the detector.
  CHECK(ref.rest_px.size() == 327);
  // Hexagonal pattern about 18.5 px apart (the image is 420 px across ~22 pins).
  CHECK(ref.pitch_px == Approx(18.5).margin(0.5));
  // The pin nearest the image centre, counted by hand from a pixel dump of rows 207-218: 109 pixels,
  // sum x = 23022, sum y = 23131 -> centre (211.211, 212.211).
  const Vec2 hand(23022.0 / 109.0, 23131.0 / 109.0);
  double best = 1e9;
  for (const auto& p : ref.rest_px) best = std::min(best, (p - hand).norm());
  constexpr double kCentroidTol = 1e-6;  // the same pixels, summed in a different order
  CHECK(best < kCentroidTol);
}

TEST_CASE("a shifted reference is tracked exactly; a light real press keeps >= 95 % of pins", "[tracker][tactip]") {
  const std::string path = tactip_data("calibration/images/image_0.png");
  const cv::Mat img = grey(path);
  const PinTrackerOptions opts;
  const PinReference ref = make_pin_reference(img, opts, path);
  SECTION("an integer shift of (5, -3) px moves every blob and its area centroid by exactly that") {
    cv::Mat shifted;
    const cv::Mat M = (cv::Mat_<double>(2, 3) << 1, 0, 5, 0, 1, -3);
    cv::warpAffine(img, shifted, M, img.size(), cv::INTER_NEAREST, cv::BORDER_CONSTANT, 0);
    const std::vector<Vec2> d = track_pins(ref, shifted, opts);
    CHECK(kept(d) == int(ref.rest_px.size()));  // every pin stays inside the 420 px image
    double worst = 0;
    for (const auto& v : d)
      if (v.allFinite()) worst = std::max(worst, (v - Vec2(5, -3)).norm());
    CHECK(worst < 1e-9);
  }
  SECTION("validation image_14 (depth 1.45 mm, shear (0.72, 2.02) mm): pins kept, field small and finite") {
    const std::vector<Vec2> d = track_pins(ref, grey(tactip_data("validation/images/image_14.png")), opts);
    CHECK(kept(d) >= int(std::ceil(0.95 * ref.rest_px.size())));
    // No pin jumps a lattice site: at this press every kept displacement stays under one pitch.
    for (const auto& v : d)
      if (v.allFinite()) CHECK(v.norm() < ref.pitch_px);
  }
}

TEST_CASE("TacTip pose path: above, pressed at (pose + shear), slid to the pose", "[import][tactip]") {
  constexpr double kTol = 1e-12;
  const double d = 0.003, sx = 0.002, sy = -0.001;
  SECTION("no tilt, no twist: the surface sits at -(shear) then slides to the apex") {
    // X_WS = (s, d) pressed, (0, 0, d) final; X_EI = X_WS^-1 -> p_EI = -(sx, sy, d), then (0, 0, -d).
    const auto path = tactip_pose_path(d, 0, 0, sx, sy, 0, 4, 0.005);
    REQUIRE(path.size() == 6);  // above, pressed, 4 slide steps
    CHECK((path[0].translation() - Vec3(-sx, -sy, 0.005)).norm() < kTol);
    CHECK((path[1].translation() - Vec3(-sx, -sy, -d)).norm() < kTol);
    CHECK((path[3].translation() - Vec3(-sx / 2, -sy / 2, -d)).norm() < kTol);
    CHECK((path[5].translation() - Vec3(0, 0, -d)).norm() < kTol);
  }
  SECTION("tilted and twisted: the apex penetrates the face by the depth in every pressed frame") {
    // The face is z_I = 0 with the body at z_I > 0, so the apex (origin of E) is at depth
    // -(p_EI . R_EI z) inside it; the robot keeps the tip at depth d whatever the tilt and twist.
    const auto path = tactip_pose_path(d, 0.3, -0.2, sx, sy, 0.07, 5, 0.005);
    for (std::size_t k = 1; k < path.size(); ++k)
      CHECK(-path[k].translation().dot(path[k].linear() * Vec3::UnitZ()) == Approx(d).margin(kTol));
    CHECK(-path[0].translation().dot(path[0].linear() * Vec3::UnitZ()) == Approx(-0.005).margin(kTol));
    // The twist goes to zero: R_EI at the end is the tilt alone.
    const Eigen::Matrix3d R_tilt =
        (Eigen::AngleAxisd(-0.2, Vec3::UnitY()) * Eigen::AngleAxisd(0.3, Vec3::UnitX())).toRotationMatrix();
    CHECK((path.back().linear() - R_tilt.transpose()).norm() < kTol);
  }
}

TEST_CASE("tactip_shear import of three samples per split reads back as tsd/1", "[import][tactip]") {
  const std::string in = tactip_data("");
  const fs::path out = sbtest::temp_path("sb_test_import_tactip");
  fs::remove_all(out);
  TactipImportOptions opts;
  opts.max_samples_per_split = 3;
  const ImportReport report = import_tactip_shear(in, out.string(), opts);
  REQUIRE(report.datasets.size() == 1);
  const Dataset ds = read_dataset(out.string());
  CHECK(ds.sensor_model == "TacTip midi");
  CHECK(ds.markers_rest_px.size() == 327);
  // targets.csv order: calibration image_1..3, validation image_14, 21, 25. Three samples are too few for the pin
  // prior, so the deep presses (image_1 at 4.0 mm, image_21 and image_25) keep no pin and are left out, said so.
  REQUIRE(ds.samples.size() == 3);
  CHECK(ds.samples[0].id == "cal_0002");
  CHECK(ds.samples[0].split == "calibration");
  CHECK(ds.samples[2].id == "val_0014");
  CHECK(ds.samples[2].split == "validation");
  CHECK(std::count_if(report.lines.begin(), report.lines.end(), [](const std::string& l) {
          return l.find("have no pin tracked") != std::string::npos && l.find("left out") != std::string::npos;
        }) == 2);
  // image_2: |shear| = 4.05 mm (0.81 of 5 mm) > |twist| 1.73 deg (0.35 of 5 deg): shear.
  CHECK(ds.samples[0].motion == "shear");
  // image_14: shear 2.15 mm (0.43) vs twist 0.41 deg (0.08): shear.
  CHECK(ds.samples[2].motion == "shear");
  CHECK(ds.samples[2].extra.at("targets").at("depth_mm").get<double>() == Approx(1.445930981));
  const SampleData s = read_sample(ds, "val_0014");
  REQUIRE(s.frames() == std::size_t(opts.slide_steps + 2));
  // Final pose: p_EI = -R_EI (0, 0, d) with R_EI = Rx(-rx) Ry(-ry), whose z is -d cos(rx) cos(ry).
  const double deg = M_PI / 180.0;
  CHECK(s.p_EI.back().z() ==
        Approx(-1.445930981e-3 * std::cos(-11.98328445 * deg) * std::cos(20.65162021 * deg)).margin(1e-12));
  for (const auto& m : s.markers_px.front()) CHECK(m.norm() == 0.0);  // frame 0: the reference
  for (const auto& m : s.markers_px[1]) CHECK(std::isnan(m.x()));     // pressed, not imaged
  CHECK(kept(s.markers_px.back()) == ds.samples[2].extra.at("pins_tracked").get<int>());
  CHECK(kept(s.markers_px.back()) >= int(std::ceil(0.95 * 327)));
  // The camera fitted to the reference's pin rings (docs/sensors.md, "Bringing a new TacTip"): principal point,
  // focal length and distance fitted with the skin's ring pitch (8 deg), dome radius and pin depth at the
  // standard TacTip's defaults and k1 = 0. The values are the ones measured there; the margins are well below
  // their sigmas (0.02 px, 0.55 px, 0.06 mm) so a changed fit shows.
  CHECK(ds.camera.pinhole());
  CHECK(ds.camera.principal_px.x() == Approx(211.4626).margin(0.005));
  CHECK(ds.camera.principal_px.y() == Approx(212.1644).margin(0.005));
  CHECK(ds.camera.distance_m == Approx(0.0503757).margin(2e-6));
  CHECK(ds.camera.focal_px == Approx(362.294).margin(0.01));
  CHECK(ds.camera.k1 == 0.0);
  const auto& desc = ds.sensor_extra.at("tactip").at("description").at("values");
  CHECK(desc.at("focal_px").at("source") == "identified");
  CHECK(desc.at("ring_pitch_deg").at("source") == "default");
  CHECK(desc.at("dome_radius_mm").at("value").get<double>() == 20.0);
  const auto& fit = ds.sensor_extra.at("tactip").at("geometry_fit");
  CHECK(fit.at("pins_used").get<int>() == 327);
  CHECK(fit.at("rings").get<int>() == 10);
  CHECK(fit.at("rms_px").get<double>() < 0.5);
  // The sensor builds from it: every pin's ray meets the pin sphere on the hemisphere, the outermost ones at the
  // outer ring's polar angle, 10 ring pitches (79.7 deg) give or take their scatter (0.6 px of ring 10's RMS is
  // about 0.3 deg there).
  const auto sensor = dataset_sensor(ds);
  double polar_max = 0;
  for (const Vec3& p : sensor->p_EM) polar_max = std::max(polar_max, std::acos((p.z() + 0.020) / 0.020));
  CHECK(polar_max * 180.0 / M_PI == Approx(fit.at("outer_ring_polar_deg").get<double>()).margin(1.0));
  fs::remove_all(out);
}

TEST_CASE("a malformed targets.csv row is an InputError naming file, line and column", "[import][tactip]") {
  const fs::path dir = sbtest::temp_path("sb_test_tactip_bad");
  fs::remove_all(dir);
  for (const char* split : {"calibration", "validation"}) {
    fs::create_directories(dir / split / "images");
    fs::copy_file(tactip_data("calibration/images/image_0.png"), dir / split / "images" / "image_0.png");
  }
  const std::string header =
      "sensor_image,object_label,pose_x,pose_y,pose_z,pose_Rx,pose_Ry,pose_Rz,shear_x,shear_y,shear_z,shear_Rx,"
      "shear_Ry,shear_Rz,object_x,object_y,object_z,object_Rx,object_Ry,object_Rz\n";
  {
    std::ofstream(dir / "calibration" / "targets.csv")
        << header << "image_1.png,surface,0,0,two,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0\n";
  }
  try {
    import_tactip_shear(dir.string(), (dir / "out").string());
    FAIL("no InputError");
  } catch (const InputError& e) {
    // pose_z is the 5th column of line 2.
    CHECK_THAT(e.what(), Catch::Contains("targets.csv:2:5"));
  }
  fs::remove_all(dir);
}

TEST_CASE("tactip_shear import with frames: the reference and the image, none where nothing was imaged",
          "[import][tactip]") {
  const std::string in = tactip_data("");
  const fs::path out = sbtest::temp_path("sb_test_import_tactip_frames");
  fs::remove_all(out);
  TactipImportOptions opts;
  opts.max_samples_per_split = 1;
  opts.frames = true;
  import_tactip_shear(in, out.string(), opts);
  const Dataset ds = read_dataset(out.string());
  REQUIRE(ds.sample("val_0014").has_frames);
  const SampleData s = read_sample(ds, "val_0014");
  REQUIRE(s.frame_paths.size() == s.frames());
  // Frame 0 is the reference, the last frame the sample's image, pixel for pixel; the pressed and
  // sliding frames between were not imaged (their markers are NaN) and have no image.
  CHECK(cv::norm(grey(s.frame_paths.front()), grey(tactip_data("validation/images/image_0.png")), cv::NORM_INF) == 0);
  CHECK(cv::norm(grey(s.frame_paths.back()), grey(tactip_data("validation/images/image_14.png")), cv::NORM_INF) == 0);
  for (std::size_t k = 1; k + 1 < s.frames(); ++k) CHECK(s.frame_paths[k].empty());
  SECTION("an imaged frame whose image is missing is an error naming it") {
    fs::remove(s.frame_paths.back());
    try {
      read_sample(ds, "val_0014");
      FAIL("no InputError");
    } catch (const InputError& e) {
      CHECK_THAT(e.what(), Catch::Contains("val_0014/frames/000011.png"));
    }
  }
  fs::remove_all(out);
}

}  // namespace test_pin_tracker
