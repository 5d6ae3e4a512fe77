// camera_misalignment's evidence (core/loop/fingerprint_camera_misalignment.hpp) and edge_constraint's
// (core/loop/fingerprint_edge_constraint.hpp): a common turn of the field, and its hold-back at the pad's sides.
#include <catch2/catch.hpp>

#include "core/loop/fingerprint_camera_misalignment.hpp"
#include "core/loop/fingerprint_edge_constraint.hpp"
#include "tests/evidence_fixtures.hpp"

namespace test_fingerprint_camera_misalignment {

using sb::Vec2;
using namespace sbtest;

namespace {

constexpr double kNoisePx = 0.02;
constexpr double kRollRad = 0.03;
constexpr double kRollTolRad = 0.003;  // atan2 over hundreds of marker-frames of ~1 px: noise ~1e-4 rad

// Presses to 1 mm at points over the grid (by sample), the model's field radial about the contact.
sb::EvidenceSplit presses(const MeasOf& meas, std::uint64_t seed) {
  const auto frames = [](int i) {
    return press_frames(grid_centre() + Vec2(20.0 * (i % 3 - 1), 15.0 * (i % 2)), 1e-3);
  };
  const auto pred = [](int, const FrameSpec& f, std::size_t j) {
    return press_field(evidence_sensor().markers_rest_px[j], f.centre_px, 3000 * f.depth_m, Vec2::Zero());
  };
  return make_split(6, frames, pred, meas, kNoisePx, seed);
}

Vec2 rolled(int, const FrameSpec&, std::size_t, const Vec2& p) {
  const double c = std::cos(kRollRad), s = std::sin(kRollRad);
  return {c * p.x() - s * p.y(), s * p.x() + c * p.y()};
}
Vec2 stronger(int, const FrameSpec&, std::size_t, const Vec2& p) { return Vec2(1.2 * p); }

}  // namespace

TEST_CASE("camera_misalignment evidence: a common turn is found, a gain is not", "[evidence][camera_misalignment]") {
  const auto fitted = [](const std::string& n) { return n == "rotation_rad" ? kRollRad : 0.0; };
  const auto e = sb::camera_misalignment_evidence(evidence_sensor(), presses(rolled, 1), presses(rolled, 2), fitted);
  INFO(e.verdict);
  CHECK(e.found);
  CHECK(std::abs(e.calibration.estimate - kRollRad) <= kRollTolRad);
  const auto none =
      sb::camera_misalignment_evidence(evidence_sensor(), presses(stronger, 3), presses(stronger, 4), fitted);
  INFO(none.verdict);
  CHECK_FALSE(none.found);
}

// Clamped sides: every marker scaled by 1 - s exp(-dist / l), s = 0.5, l = 2 mm. The two halves' gains follow
// g0 (1 - s w) exactly up to the profile's spread within each half (w is not one value per half): s is read within
// kStrengthTol. A gain error (1.2 x everywhere) holds nothing back: s = 0.
constexpr double kStrengthTol = 0.1;
TEST_CASE("edge_constraint evidence: a field held back at the sides is found, a gain is not",
          "[evidence][edge_constraint]") {
  const sb::Sensor& s = evidence_sensor();
  const Vec2 half = 0.5 * s.gel.size_m;
  const auto clamped = [&](int, const FrameSpec&, std::size_t j, const Vec2& p) {
    const sb::Vec3& q = s.p_EM[j];
    const double dist = std::max(0.0, std::min(half.x() - std::abs(q.x()), half.y() - std::abs(q.y())));
    return Vec2(p * (1 - 0.5 * std::exp(-dist / 0.002)));
  };
  // Broad presses (the field reaches the sides): the model's Gaussian is 2 pitches wide, so press at the sides too.
  const auto frames = [](int i) {
    return press_frames(grid_centre() + Vec2(90.0 * (i % 3 - 1), 60.0 * (i % 2 ? 1 : -1)), 1e-3);
  };
  const auto pred = [](int, const FrameSpec& f, std::size_t j) {
    return press_field(evidence_sensor().markers_rest_px[j], f.centre_px, 3000 * f.depth_m, Vec2::Zero());
  };
  const auto fitted = [](const std::string& n) { return n == "strength" ? 0.5 : (n == "length_m" ? 0.002 : 0.0); };
  const auto e = sb::edge_constraint_evidence(s, make_split(6, frames, pred, clamped, kNoisePx, 5),
                                              make_split(6, frames, pred, clamped, kNoisePx, 6), fitted);
  INFO(e.verdict);
  CHECK(e.found);
  CHECK(std::abs(e.calibration.estimate - 0.5) <= kStrengthTol);
  const auto none = sb::edge_constraint_evidence(s, make_split(6, frames, pred, stronger, kNoisePx, 7),
                                                 make_split(6, frames, pred, stronger, kNoisePx, 8), fitted);
  INFO(none.verdict);
  CHECK_FALSE(none.found);
}

}  // namespace test_fingerprint_camera_misalignment
