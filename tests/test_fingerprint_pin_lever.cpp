// pin_lever's evidence (core/loop/fingerprint_pin_lever.hpp): the indented pins' outward shift that is there at
// first touch and does not grow with depth.
#include <catch2/catch.hpp>

#include "core/loop/fingerprint_pin_lever.hpp"
#include "tests/evidence_fixtures.hpp"

namespace test_fingerprint_pin_lever {

using sb::Vec2;
using namespace sbtest;

namespace {

constexpr double kNoisePx = 0.02;
constexpr double kLever = 0.01;      // px outward per px from the contact centre, whatever the depth
constexpr double kLeverTol = 0.002;  // the fit over ~10 markers x 10 frames at 0.02 px noise: ~1e-4 per sample
constexpr double kRadiusPx = 60;

double marker_depth(const FrameSpec& f, std::size_t j) {
  const double r2 = (evidence_sensor().markers_rest_px[j] - f.centre_px).squaredNorm();
  return std::max(0.0, f.depth_m * (1 - r2 / (kRadiusPx * kRadiusPx)));
}

sb::EvidenceSplit presses(const MeasOf& meas, std::uint64_t seed) {
  const auto frames = [](int i) { return press_frames(grid_centre() + Vec2(5.0 * i, 3.0 * i), 1e-3); };
  const auto pred = [](int, const FrameSpec& f, std::size_t j) {
    return press_field(evidence_sensor().markers_rest_px[j], f.centre_px, 3000 * f.depth_m, Vec2::Zero());
  };
  return make_split(6, frames, pred, meas, kNoisePx, seed, marker_depth);
}

// The lever: kLever rho outward on every indented marker, set at first touch.
Vec2 lever(int, const FrameSpec& f, std::size_t j, const Vec2& p) {
  const Vec2 out = evidence_sensor().markers_rest_px[j] - f.centre_px;
  return marker_depth(f, j) > 0 ? Vec2(p + kLever * out) : p;
}
// A form error of the dilation: outward, growing with the marker's penetration (kLever rho at 1 mm).
Vec2 growing(int, const FrameSpec& f, std::size_t j, const Vec2& p) {
  const Vec2 out = evidence_sensor().markers_rest_px[j] - f.centre_px;
  return p + kLever * (marker_depth(f, j) / 1e-3) * out;
}

double fitted(const std::string& n) { return n == "gain" ? 1.0 : 0.0; }

}  // namespace

TEST_CASE("pin_lever evidence: an outward shift set at first touch is found", "[evidence][pin_lever]") {
  const auto e = sb::pin_lever_evidence(evidence_sensor(), presses(lever, 1), presses(lever, 2), fitted);
  INFO(e.verdict);
  CHECK(e.found);
  CHECK(std::abs(e.calibration.estimate - kLever) <= kLeverTol);
}

TEST_CASE("pin_lever evidence: an outward shift growing with depth is not found", "[evidence][pin_lever]") {
  const auto e = sb::pin_lever_evidence(evidence_sensor(), presses(growing, 3), presses(growing, 4), fitted);
  INFO(e.verdict);
  CHECK_FALSE(e.found);
  CHECK(std::abs(e.calibration.estimate) <= kLeverTol);
}

}  // namespace test_fingerprint_pin_lever
