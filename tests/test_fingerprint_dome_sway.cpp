// dome_sway's evidence (core/loop/fingerprint_dome_sway.hpp): the far markers dragged along the slide.
#include <catch2/catch.hpp>

#include "core/loop/fingerprint_dome_sway.hpp"
#include "tests/evidence_fixtures.hpp"

namespace test_fingerprint_dome_sway {

using sb::Vec2;
using namespace sbtest;

namespace {

constexpr double kNoisePx = 0.02;
constexpr double kSwayPx = 0.3;      // the whole array's shift along the slide
constexpr double kSwayTolPx = 0.02;  // the far markers' mean: noise / sqrt(markers x frames) << this

Vec2 slide_dir(int i) {
  const Vec2 d[4] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  return d[i % 4];
}

// Slides of 15 px from the grid centre along +x, -x, +y, -y (by sample); the model's field: a press plus 2 px
// of shear along the slide, local to the contact.
sb::EvidenceSplit slides(const MeasOf& meas, std::uint64_t seed) {
  const auto frames = [](int i) { return slide_frames(grid_centre(), slide_dir(i), 1e-3, 15.0); };
  const auto pred = [](int i, const FrameSpec& f, std::size_t j) {
    return press_field(evidence_sensor().markers_rest_px[j], f.centre_px, 3000 * f.depth_m,
                       f.travel_px > 0 ? Vec2(2.0 * slide_dir(i)) : Vec2::Zero());
  };
  return make_split(8, frames, pred, meas, kNoisePx, seed);
}

double fitted(const std::string& n) { return n == "compliance_m" ? 5e-4 : 0.0; }

}  // namespace

// Every marker moves kSwayPx along the slide in the slide frames: the far markers' residual reads it.
TEST_CASE("dome_sway evidence: the whole array moving with the slide is found", "[evidence][dome_sway]") {
  const auto sway = [](int i, const FrameSpec& f, std::size_t, const Vec2& p) {
    return f.travel_px >= 1.0 ? Vec2(p + kSwayPx * slide_dir(i)) : p;
  };
  const auto e = sb::dome_sway_evidence(evidence_sensor(), slides(sway, 1), slides(sway, 2), fitted);
  INFO(e.verdict);
  CHECK(e.found);
  CHECK(std::abs(e.calibration.estimate - kSwayPx) <= kSwayTolPx);
}

// A kernel 30 % too weak: the residual is 0.3 x the model's field, which has died away where the far markers are:
// its drag is no larger than the model's own field there. Not found.
TEST_CASE("dome_sway evidence: a kernel's gain error is not the array moving", "[evidence][dome_sway]") {
  const auto gain = [](int, const FrameSpec&, std::size_t, const Vec2& p) { return Vec2(1.3 * p); };
  const auto e = sb::dome_sway_evidence(evidence_sensor(), slides(gain, 3), slides(gain, 4), fitted);
  INFO(e.verdict);
  CHECK_FALSE(e.found);
}

}  // namespace test_fingerprint_dome_sway
