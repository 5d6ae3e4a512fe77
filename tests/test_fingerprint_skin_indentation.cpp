// skin_indentation's evidence (core/loop/fingerprint_skin_indentation.hpp): indented markers converging on the
// principal point, told apart from converging on the contact by presses off the image centre.
#include <catch2/catch.hpp>

#include "core/loop/fingerprint_skin_indentation.hpp"
#include "tests/evidence_fixtures.hpp"

namespace test_fingerprint_skin_indentation {

using sb::Vec2;
using namespace sbtest;

namespace {

constexpr double kNoisePx = 0.02;
constexpr double kPxPerM = 2000;  // 2 px per mm of a marker's penetration
// The two-regressor fit is exact up to noise over ~10 indented markers x 10 frames: 10 % of the rate covers it.
constexpr double kRateRelTol = 0.10;
constexpr double kRadiusPx = 60;  // the indenter's footprint: a marker inside at r is indented (1 - r^2/R^2) delta

sb::Sensor pinhole_sensor() {
  sb::Sensor s = evidence_sensor();
  s.camera.model = sb::CameraModel::kPinhole;
  return s;
}

double marker_depth(const FrameSpec& f, std::size_t j) {
  const double r2 = (evidence_sensor().markers_rest_px[j] - f.centre_px).squaredNorm();
  return std::max(0.0, f.depth_m * (1 - r2 / (kRadiusPx * kRadiusPx)));
}

Vec2 unit(const Vec2& v) { return v.norm() > 1.0 ? Vec2(v.normalized()) : Vec2::Zero(); }

// Presses to 1 mm at 70-100 px from the principal point, in four directions.
sb::EvidenceSplit presses(const MeasOf& meas, std::uint64_t seed) {
  const auto frames = [](int i) {
    const Vec2 d[4] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
    return press_frames(grid_centre() + (70.0 + 10 * (i % 4)) * d[i % 4], 1e-3);
  };
  const auto pred = [](int, const FrameSpec& f, std::size_t j) {
    return press_field(evidence_sensor().markers_rest_px[j], f.centre_px, 3000 * f.depth_m, Vec2::Zero());
  };
  return make_split(8, frames, pred, meas, kNoisePx, seed, marker_depth);
}

Vec2 to_centre(int, const FrameSpec& f, std::size_t j, const Vec2& p) {
  const Vec2& m = evidence_sensor().markers_rest_px[j];
  return p + kPxPerM * marker_depth(f, j) * unit(grid_centre() - m);
}
Vec2 to_contact(int, const FrameSpec& f, std::size_t j, const Vec2& p) {
  const Vec2& m = evidence_sensor().markers_rest_px[j];
  return p + kPxPerM * marker_depth(f, j) * unit(f.centre_px - m);
}

double fitted(const std::string& n) { return n == "gain" ? 0.5 : 0.0; }

}  // namespace

TEST_CASE("skin_indentation evidence: convergence on the image centre is found", "[evidence][skin_indentation]") {
  const sb::Sensor s = pinhole_sensor();
  const auto e = sb::skin_indentation_evidence(s, presses(to_centre, 1), presses(to_centre, 2), fitted);
  INFO(e.verdict);
  CHECK(e.found);
  CHECK(std::abs(e.calibration.estimate - kPxPerM) <= kRateRelTol * kPxPerM);
}

// The same size of motion towards the contact centre (a contact model's symmetric error): u_pp's coefficient is 0.
TEST_CASE("skin_indentation evidence: convergence on the contact is not found", "[evidence][skin_indentation]") {
  const sb::Sensor s = pinhole_sensor();
  const auto e = sb::skin_indentation_evidence(s, presses(to_contact, 3), presses(to_contact, 4), fitted);
  INFO(e.verdict);
  CHECK_FALSE(e.found);
  CHECK(std::abs(e.calibration.estimate) <= kRateRelTol * kPxPerM);
}

TEST_CASE("skin_indentation evidence: an orthographic camera has none", "[evidence][skin_indentation]") {
  const auto e = sb::skin_indentation_evidence(evidence_sensor(), presses(to_centre, 5), presses(to_centre, 6), fitted);
  CHECK_FALSE(e.found);
  CHECK_THAT(e.verdict, Catch::Contains("orthographic"));
}

}  // namespace test_fingerprint_skin_indentation
