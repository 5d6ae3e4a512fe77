// tracker_bias's evidence (core/loop/fingerprint_tracker_bias.hpp) and gravity_preload's
// (core/loop/fingerprint_gravity_preload.hpp): offsets fixed in the image, against form errors that follow the load.
#include <catch2/catch.hpp>

#include "core/loop/fingerprint_gravity_preload.hpp"
#include "core/loop/fingerprint_tracker_bias.hpp"
#include "tests/evidence_fixtures.hpp"

namespace test_fingerprint_tracker_bias {

using sb::Vec2;
using namespace sbtest;

namespace {

constexpr double kNoisePx = 0.02;
constexpr double kBiasPx = 0.2;
constexpr double kBiasTolPx = 0.02;  // per-sample means over hundreds of marker-frames: noise ~1e-3 px

Vec2 slide_dir(int i) {
  const Vec2 d[4] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  return d[i % 4];
}

// Slides of 15 px along +x, -x, +y, -y (by sample), the model's field a press plus 2 px of shear along the slide.
sb::EvidenceSplit slides(const MeasOf& meas, std::uint64_t seed) {
  const auto frames = [](int i) { return slide_frames(grid_centre(), slide_dir(i), 1e-3, 15.0); };
  const auto pred = [](int i, const FrameSpec& f, std::size_t j) {
    return press_field(evidence_sensor().markers_rest_px[j], f.centre_px, 3000 * f.depth_m,
                       f.travel_px > 0 ? Vec2(2.0 * slide_dir(i)) : Vec2::Zero());
  };
  return make_split(8, frames, pred, meas, kNoisePx, seed);
}

// A form error that follows the load: the shear 20 % stronger along the slide (opposite signs over the samples).
Vec2 shear_gain(int i, const FrameSpec& f, std::size_t j, const Vec2& p) {
  const Vec2 shear = press_field(evidence_sensor().markers_rest_px[j], f.centre_px, 0,
                                 f.travel_px > 0 ? Vec2(2.0 * slide_dir(i)) : Vec2::Zero());
  return p + 0.2 * shear;
}

double fitted_bias(const std::string& n) { return n == "bias_x_px" ? kBiasPx : 0.0; }
double fitted_preload(const std::string& n) { return n == "gx_px" ? kBiasPx : (n == "width_m" ? 0.003 : 0.0); }

}  // namespace

TEST_CASE("tracker_bias evidence: an offset on the moving markers in every direction is found",
          "[evidence][tracker_bias]") {
  const auto bias = [](int, const FrameSpec&, std::size_t, const Vec2& p) {
    return p.norm() > 0.5 ? Vec2(p + Vec2(kBiasPx, 0)) : p;
  };
  const auto e = sb::tracker_bias_evidence(evidence_sensor(), slides(bias, 1), slides(bias, 2), fitted_bias);
  INFO(e.verdict);
  CHECK(e.found);
  CHECK(std::abs(e.calibration.estimate - kBiasPx) <= kBiasTolPx);
}

TEST_CASE("tracker_bias evidence: a shear error that turns with the slide is not found", "[evidence][tracker_bias]") {
  const auto e =
      sb::tracker_bias_evidence(evidence_sensor(), slides(shear_gain, 3), slides(shear_gain, 4), fitted_bias);
  INFO(e.verdict);
  CHECK_FALSE(e.found);
}

// The preload: kBiasPx along x, a Gaussian of 3 mm (47 px) about the contact, in every frame in contact; read
// where the presses are, its weighted mean at the contact is kBiasPx times the mean of the squared Gaussian over
// its own weights (sum w^2 / sum w): about 0.5-0.6 of it on this grid, so only the sign and a lower bound are checked.
TEST_CASE("gravity_preload evidence: a fixed shear at the contact is found, a symmetric error is not",
          "[evidence][gravity_preload]") {
  const double w_px = 0.003 / evidence_sensor().camera.metres_per_px();
  const auto preload = [&](int, const FrameSpec& f, std::size_t j, const Vec2& p) {
    const double d2 = (evidence_sensor().markers_rest_px[j] - f.centre_px).squaredNorm();
    return f.in_contact ? Vec2(p + kBiasPx * std::exp(-d2 / (2 * w_px * w_px)) * Vec2(1, 0)) : p;
  };
  const auto found =
      sb::gravity_preload_evidence(evidence_sensor(), slides(preload, 5), slides(preload, 6), fitted_preload);
  INFO(found.verdict);
  CHECK(found.found);
  CHECK(found.calibration.estimate > 0.3 * kBiasPx);
  const auto radial = [](int, const FrameSpec&, std::size_t, const Vec2& p) { return Vec2(1.2 * p); };
  const auto none =
      sb::gravity_preload_evidence(evidence_sensor(), slides(radial, 7), slides(radial, 8), fitted_preload);
  INFO(none.verdict);
  CHECK_FALSE(none.found);
}

}  // namespace test_fingerprint_tracker_bias
