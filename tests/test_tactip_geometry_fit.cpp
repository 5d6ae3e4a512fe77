// The TacTip geometry fit (core/sensor/tactip_geometry_fit): pins laid on a known pin sphere in the ring
// pattern, projected through a known pinhole camera, and the fit recovering what it fits.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "core/base/data_root.hpp"
#include "core/base/error.hpp"
#include "core/sensor/tactip_geometry_fit.hpp"
#include "core/tracking/pin_tracker.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_tactip_geometry_fit {

using namespace sb;
namespace fs = std::filesystem;

namespace {

constexpr double kDeg = M_PI / 180.0;

// A TacTip-like truth: R = 20 mm, pins 3 mm deep (r_p = 17 mm), the camera a = (D - R) / r_p = 2 away from the
// dome centre (D = 54 mm), f = 400 px, the apex pin at (205.3, 213.7) px, rings 8 deg apart, phi0 = 0.1 rad.
struct Truth {
  double R = 0.020, depth = 0.003, theta = 8.0 * kDeg, phi0 = 0.1;
  Camera camera;
  Truth() {
    camera.model = CameraModel::kPinhole;
    camera.width_px = camera.height_px = 420;
    camera.focal_px = 400.0;
    camera.distance_m = 0.054;
    camera.k1 = 0.0;
    camera.principal_px = Vec2(205.3, 213.7);
  }
};

// Every pin of `rings` rings (1 + 3 rings (rings + 1) of them), in a shuffled order (the fit must not rely on
// the order), less the pins `drop` says to leave out.
std::vector<Vec2> ring_pins(const Truth& t, int rings, const std::vector<TactipPinSite>& drop = {}) {
  std::vector<Vec2> pins;
  for (int i = 0; i <= rings; ++i)
    for (int k = 0; k < std::max(1, 6 * i); ++k) {
      const TactipPinSite s{i, k};
      if (std::any_of(drop.begin(), drop.end(), [&](const TactipPinSite& d) { return d.ring == i && d.slot == k; }))
        continue;
      pins.push_back(tactip_pin_px(t.camera, t.R, t.depth, t.theta, t.phi0, s));
    }
  // A fixed permutation: stride 97 through the list (coprime with every size used here).
  std::vector<Vec2> shuffled;
  for (std::size_t j = 0; j < pins.size(); ++j) shuffled.push_back(pins[(j * 97) % pins.size()]);
  return shuffled;
}

TactipGeometryFitOptions start_from(const Truth& t) {
  TactipGeometryFitOptions o;
  o.dome_radius_m = t.R;
  o.pin_depth_m = t.depth;
  o.initial = t.camera;
  return o;
}

}  // namespace

TEST_CASE("TacTip pin model: a ring-1 pin by hand", "[sensor][tactip_fit]") {
  const Truth t;
  // Pin (1, 0): polar angle theta = 8 deg, azimuth phi0. Its image radius is
  //   f r_p sin(theta) / (D - R + r_p cos(theta)) = f sin(theta) / (a + cos(theta)), a = 34 / 17 = 2,
  //   = 400 * 0.13917310 / (2 + 0.99026807) = 55.669240 / 2.99026807 = 18.616804 px,
  // along (cos 0.1, sin 0.1) from the principal point.
  constexpr double kTol = 1e-5;  // px: the 8 digits carried above
  const Vec2 uv = tactip_pin_px(t.camera, t.R, t.depth, t.theta, t.phi0, {1, 0});
  CHECK((uv - t.camera.principal_px).norm() == Approx(18.616804).margin(kTol));
  CHECK(std::atan2(uv.y() - 213.7, uv.x() - 205.3) == Approx(0.1).margin(1e-12));
  // The apex pin is seen at the principal point; pin (2, 3) at azimuth phi0 + 2 pi 3 / 12 = phi0 + 90 deg.
  CHECK((tactip_pin_px(t.camera, t.R, t.depth, t.theta, t.phi0, {0, 0}) - t.camera.principal_px).norm() < 1e-12);
  const Vec2 d = tactip_pin_px(t.camera, t.R, t.depth, t.theta, t.phi0, {2, 3}) - t.camera.principal_px;
  CHECK(std::atan2(d.y(), d.x()) == Approx(0.1 + M_PI / 2).margin(1e-12));
}

TEST_CASE("TacTip rings: every pin to its ring and slot, rim pins missing, order shuffled", "[sensor][tactip_fit]") {
  const Truth t;
  // 10 rings (331 pins), four rim pins missing as in the real reference (327 found).
  const std::vector<TactipPinSite> drop{{10, 0}, {10, 17}, {10, 33}, {10, 59}};
  const std::vector<Vec2> pins = ring_pins(t, 10, drop);
  REQUIRE(pins.size() == 327);
  const TactipRings rings = assign_tactip_rings(pins, "synthetic");
  CHECK(rings.assigned == 327);
  CHECK(rings.ring_radius_px.size() == 11);
  CHECK(rings.azimuth_rad == Approx(0.1).margin(1e-9));
  // Each assigned site projects back onto its pin.
  for (std::size_t j = 0; j < pins.size(); ++j)
    CHECK((tactip_pin_px(t.camera, t.R, t.depth, t.theta, t.phi0, rings.sites[j]) - pins[j]).norm() < 1e-9);
}

TEST_CASE("TacTip geometry fit recovers a known camera and pin pitch", "[sensor][tactip_fit]") {
  const Truth t;
  const std::vector<Vec2> pins = ring_pins(t, 10, {{10, 5}, {9, 40}});
  // Noise-free pins: the fit reaches the truth to the solver's tolerance; 1e-6 relative is far below anything
  // a pixel could tell.
  constexpr double kRel = 1e-6;
  SECTION("D and theta fitted, f and k1 fixed at the truth; the start 10 mm off in D") {
    TactipGeometryFitOptions o = start_from(t);
    o.initial.distance_m = 0.044;
    const TactipGeometryFit fit = fit_tactip_geometry(pins, o, "synthetic");
    CHECK(fit.pins_used == 329);
    CHECK(fit.camera.distance_m == Approx(0.054).epsilon(kRel));
    CHECK(fit.ring_pitch_rad == Approx(8.0 * kDeg).epsilon(kRel));
    CHECK(fit.camera.principal_px.x() == Approx(205.3).epsilon(kRel));
    CHECK(fit.camera.principal_px.y() == Approx(213.7).epsilon(kRel));
    CHECK(fit.azimuth_rad == Approx(0.1).epsilon(kRel));
    CHECK(fit.camera.focal_px == 400.0);  // fixed
    CHECK(fit.rms_px < 1e-6);
    CHECK(fit.outer_ring_polar_rad() == Approx(80.0 * kDeg).epsilon(kRel));
    // A zero residual makes every sigma zero, not NaN: the free set is identifiable.
    CHECK(fit.covariance_ok);
    CHECK(std::isnan(fit.sigma_focal_px));
  }
  SECTION("f and theta fitted with D fixed; distortion k1 = -0.1 fitted from zero") {
    Truth td;
    td.camera.k1 = -0.1;
    const std::vector<Vec2> pins_k = ring_pins(td, 10);
    TactipGeometryFitOptions o = start_from(td);
    o.fit_focal = true;
    o.fit_distance = false;
    o.fit_k1 = true;
    o.initial.focal_px = 350.0;
    o.initial.k1 = 0.0;
    const TactipGeometryFit fit = fit_tactip_geometry(pins_k, o, "synthetic");
    CHECK(fit.camera.focal_px == Approx(400.0).epsilon(kRel));
    CHECK(fit.camera.k1 == Approx(-0.1).epsilon(1e-5));
    CHECK(fit.ring_pitch_rad == Approx(8.0 * kDeg).epsilon(kRel));
    CHECK(fit.camera.distance_m == 0.054);  // fixed
  }
  SECTION("the skin's ring pitch fixed (the import's way): f and D fitted, started 12 % and 8 mm off") {
    TactipGeometryFitOptions o = start_from(t);
    o.fit_ring_pitch = false;
    o.ring_pitch_rad = 8.0 * kDeg;
    o.fit_focal = true;
    o.initial.focal_px = 350.0;
    o.initial.distance_m = 0.046;
    const TactipGeometryFit fit = fit_tactip_geometry(pins, o, "synthetic");
    CHECK(fit.camera.focal_px == Approx(400.0).epsilon(kRel));
    CHECK(fit.camera.distance_m == Approx(0.054).epsilon(kRel));
    CHECK(fit.ring_pitch_rad == 8.0 * kDeg);  // fixed
    CHECK(std::isnan(fit.sigma_pitch_rad));
    o.ring_pitch_rad = 0;
    CHECK_THROWS_AS(fit_tactip_geometry(pins, o, "synthetic"), InputError);
  }
  SECTION("noisy pins: the residual is the noise, the fitted D within 3 sigma") {
    // A deterministic zero-mean perturbation of 0.3 px amplitude per axis: (+-0.3, -+0.3) alternating,
    // so each axis has RMS 0.3 px and the per-pin RMS norm is 0.3 sqrt 2 = 0.424 px.
    std::vector<Vec2> noisy = pins;
    for (std::size_t j = 0; j < noisy.size(); ++j) noisy[j] += (j % 2 ? 0.3 : -0.3) * Vec2(1.0, -1.0);
    TactipGeometryFitOptions o = start_from(t);
    const TactipGeometryFit fit = fit_tactip_geometry(noisy, o, "synthetic");
    CHECK(fit.rms_px == Approx(0.3 * std::sqrt(2.0)).epsilon(0.05));
    REQUIRE(fit.covariance_ok);
    CHECK(fit.sigma_distance_m > 0.0);
    CHECK(std::abs(fit.camera.distance_m - 0.054) < 3.0 * fit.sigma_distance_m + 1e-9);
  }
}

TEST_CASE("TacTip geometry fit fails cleanly on what it cannot fit", "[sensor][tactip_fit]") {
  const Truth t;
  const TactipGeometryFitOptions o = start_from(t);
  SECTION("too few pins: the apex and ring 1 only") {
    const std::vector<Vec2> pins = ring_pins(t, 1);  // 7 pins
    try {
      fit_tactip_geometry(pins, o, "ref.png");
      FAIL("no InputError");
    } catch (const InputError& e) {
      CHECK_THAT(e.what(), Catch::Contains("ref.png") && Catch::Contains("7 pins") && Catch::Contains("at least 19"));
    }
  }
  SECTION("two rings only (19 pins): no curvature to fit") {
    try {
      fit_tactip_geometry(ring_pins(t, 2), o, "ref.png");
      FAIL("no InputError");
    } catch (const InputError& e) {
      CHECK_THAT(e.what(), Catch::Contains("only 2 pin rings"));
    }
  }
  SECTION("a square grid is not the ring pattern") {
    std::vector<Vec2> grid;
    for (int r = 0; r < 15; ++r)
      for (int c = 0; c < 15; ++c) grid.emplace_back(70.0 + 20.0 * c, 70.0 + 20.0 * r);
    // The centre pin has 4 neighbours at 20 px and 4 at 28.3 px: no six at one distance.
    try {
      fit_tactip_geometry(grid, o, "ref.png");
      FAIL("no InputError");
    } catch (const InputError& e) {
      CHECK_THAT(e.what(), Catch::Contains("not the TacTip ring pattern"));
    }
  }
  SECTION("an orthographic starting camera") {
    TactipGeometryFitOptions ortho = o;
    ortho.initial = Camera{};
    CHECK_THROWS_AS(fit_tactip_geometry(ring_pins(t, 5), ortho, "ref.png"), InputError);
  }
}

namespace {

// The rest pins of the real reference (../shared/data/raw/tactip_shear), as the import detects them.
std::vector<Vec2> reference_pins() {
  const char* env = std::getenv("SHEARBENCH_DATA");
  const std::string root = env && *env ? std::string(env) : resolve_data_root();
  const std::string path = (fs::path(root) / "raw/tactip_shear/calibration/images/image_0.png").string();
  if (!fs::exists(path)) FAIL("test data missing: " << path << " (set SHEARBENCH_DATA)");
  return make_pin_reference(cv::imread(path, cv::IMREAD_GRAYSCALE), PinTrackerOptions{}, path).rest_px;
}

// The import's starting values (core/sensor/tactip_sensor_camera.cpp): R 20 mm, pins 3 mm deep, f = 210 / tan 30
// deg, D such that the pin sphere's equator is seen at 210 px, k1 = 0.
TactipGeometryFitOptions import_start() {
  TactipGeometryFitOptions o;
  o.initial.model = CameraModel::kPinhole;
  o.initial.width_px = o.initial.height_px = 420;
  o.initial.focal_px = 210.0 / std::tan(M_PI / 6.0);
  o.initial.distance_m = 0.020 + o.initial.focal_px * 0.017 / 210.0;
  o.initial.principal_px = Vec2(209.5, 209.5);
  return o;
}

}  // namespace

// What one image determines (docs/sensors.md, "The TacTip's geometry fitted from the reference image", whose
// table these values are; `build/shearbench_tests "TacTip reference*" -s` prints them). The margins hold the
// measured values to well under their sigmas, so a change of the detector or the fit shows here.
TEST_CASE("TacTip reference: what its pin rings determine and what they cannot", "[sensor][tactip_fit]") {
  const std::vector<Vec2> pins = reference_pins();
  REQUIRE(pins.size() == 327);
  constexpr double kDeg = 180.0 / M_PI;
  const TactipGeometryFitOptions start = import_start();
  // The import's choice: principal point, D (so a = (D - R) / r_p) and theta fitted; f and k1 fixed.
  const TactipGeometryFit d = fit_tactip_geometry(pins, start, "image_0.png");
  CHECK(d.pins_used == 327);
  CHECK(d.rings.ring_radius_px.size() == 11);
  CHECK(d.rms_px == Approx(0.452).margin(0.001));
  CHECK(d.max_px == Approx(1.46).margin(0.01));
  CHECK(d.camera.principal_px.x() == Approx(211.462).margin(0.002));
  CHECK(d.camera.principal_px.y() == Approx(212.164).margin(0.002));
  CHECK(d.sigma_principal_px.x() == Approx(0.018).margin(0.001));
  CHECK(d.camera.distance_m * 1e3 == Approx(50.385).margin(0.002));
  CHECK(d.sigma_distance_m * 1e3 == Approx(0.044).margin(0.001));
  CHECK(d.ring_pitch_rad * kDeg == Approx(7.970).margin(0.001));
  CHECK(d.outer_ring_polar_rad() * kDeg == Approx(79.70).margin(0.01));
  CHECK(d.azimuth_rad * kDeg == Approx(-0.356).margin(0.001));
  SECTION("the residual's structure: ring offsets and scatter, no sign of a tilted camera") {
    // Per ring, the pins' residual split into radial (along the pin's image radius) and tangential parts; the
    // radial part's mean, its first azimuthal harmonic (a ring off-centre: a camera tilted against the dome's
    // axis shifts the rings by amounts growing with their radius) and its second (an elliptic ring).
    double mean_inner_min = 1e9, mean_inner_max = -1e9, mean_mid_max = -1e9, h1_max = 0, h2_max = 0, tan_sd_max = 0;
    for (int i = 1; i <= 10; ++i) {
      std::vector<double> er, et, phi;
      for (std::size_t j = 0; j < pins.size(); ++j) {
        if (d.rings.sites[j].ring != i) continue;
        const Vec2 m = tactip_pin_px(d.camera, 0.020, 0.003, d.ring_pitch_rad, d.azimuth_rad, d.rings.sites[j]);
        const Vec2 radial = (m - d.camera.principal_px).normalized(), e = pins[j] - m;
        er.push_back(e.dot(radial));
        et.push_back(radial.x() * e.y() - radial.y() * e.x());
        phi.push_back(std::atan2(radial.y(), radial.x()));
      }
      const double n = double(er.size());
      double mean = 0, tmean = 0;
      for (std::size_t k = 0; k < er.size(); ++k) {
        mean += er[k] / n;
        tmean += et[k] / n;
      }
      Eigen::Vector4d h = Eigen::Vector4d::Zero();
      double tvar = 0;
      for (std::size_t k = 0; k < er.size(); ++k) {
        h += 2.0 / n * (er[k] - mean) *
             Eigen::Vector4d(std::cos(phi[k]), std::sin(phi[k]), std::cos(2 * phi[k]), std::sin(2 * phi[k]));
        tvar += (et[k] - tmean) * (et[k] - tmean) / n;
      }
      if (i <= 5) {
        mean_inner_min = std::min(mean_inner_min, mean);
        mean_inner_max = std::max(mean_inner_max, mean);
      } else if (i <= 8) {
        mean_mid_max = std::max(mean_mid_max, mean);
      }
      h1_max = std::max(h1_max, h.head<2>().norm());
      h2_max = std::max(h2_max, h.tail<2>().norm());
      tan_sd_max = std::max(tan_sd_max, std::sqrt(tvar));
    }
    // Measured: rings 1..5 sit +0.16 .. +0.34 px outside the model, rings 6..8 -0.08 .. -0.20 px inside; the
    // first harmonic stays 0.12 .. 0.31 px up to ring 9 (0.41 on ring 10, four pins short), not growing with
    // the radius; the second is at most 0.17 px; the tangential scatter grows to 0.49 px on ring 10.
    CHECK(mean_inner_min == Approx(0.158).margin(0.002));
    CHECK(mean_inner_max == Approx(0.343).margin(0.002));
    CHECK(mean_mid_max == Approx(-0.084).margin(0.002));
    CHECK(h1_max == Approx(0.408).margin(0.002));
    CHECK(h2_max == Approx(0.168).margin(0.002));
    CHECK(tan_sd_max == Approx(0.487).margin(0.002));
  }
  SECTION("the pin depth only moves D: a = (D - R) / r_p stays 1.787") {
    TactipGeometryFitOptions o = start;
    o.pin_depth_m = 0.001;
    const TactipGeometryFit f1 = fit_tactip_geometry(pins, o, "image_0.png");
    CHECK((f1.camera.distance_m - 0.020) / 0.019 == Approx((d.camera.distance_m - 0.020) / 0.017).epsilon(1e-6));
    CHECK(f1.rms_px == Approx(d.rms_px).epsilon(1e-6));
  }
  SECTION("f with D (k1 = 0): determined only through fifth order, f = 438 +- 17 px for 0.015 px of RMS") {
    TactipGeometryFitOptions o = start;
    o.fit_focal = true;
    const TactipGeometryFit fd = fit_tactip_geometry(pins, o, "image_0.png");
    CHECK(fd.covariance_ok);
    CHECK(fd.camera.focal_px == Approx(438.3).margin(0.1));
    CHECK(fd.sigma_focal_px == Approx(17.3).margin(0.1));
    CHECK(fd.camera.distance_m * 1e3 == Approx(51.73).margin(0.01));
    CHECK(fd.ring_pitch_rad * kDeg == Approx(6.83).margin(0.01));
    CHECK(fd.rms_px == Approx(0.437).margin(0.001));
  }
  SECTION("k1 with D (f fixed): k1 trades with a at third order, k1 = -0.17 +- 0.05, D = 45.2 +- 2.1 mm") {
    TactipGeometryFitOptions o = start;
    o.fit_k1 = true;
    const TactipGeometryFit dk = fit_tactip_geometry(pins, o, "image_0.png");
    CHECK(dk.covariance_ok);
    CHECK(dk.camera.k1 == Approx(-0.168).margin(0.001));
    CHECK(dk.sigma_k1 == Approx(0.050).margin(0.001));
    CHECK(dk.camera.distance_m * 1e3 == Approx(45.25).margin(0.01));
    CHECK(dk.sigma_distance_m * 1e3 == Approx(2.13).margin(0.01));
    CHECK(dk.rms_px == Approx(0.437).margin(0.001));
  }
  SECTION("f, D and k1 together: not identifiable (no sigmas)") {
    TactipGeometryFitOptions o = start;
    o.fit_focal = o.fit_k1 = true;
    const TactipGeometryFit all = fit_tactip_geometry(pins, o, "image_0.png");
    CHECK_FALSE(all.covariance_ok);
    CHECK(all.covariance_rcond < 1e-12);
    CHECK(std::isnan(all.sigma_focal_px));
  }
  SECTION("f = 300 px puts the outer ring past the hemisphere's rim (92.6 deg)") {
    TactipGeometryFitOptions o = start;
    o.initial.focal_px = 300.0;
    const TactipGeometryFit f300 = fit_tactip_geometry(pins, o, "image_0.png");
    CHECK(f300.outer_ring_polar_rad() * kDeg == Approx(92.6).margin(0.1));
    CHECK(f300.rms_px == Approx(0.556).margin(0.001));
  }
}

}  // namespace test_tactip_geometry_fit
