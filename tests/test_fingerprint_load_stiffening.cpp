// load_stiffening's evidence (core/loop/fingerprint_load_stiffening.hpp) and spread_saturation's
// (core/loop/fingerprint_spread_saturation.hpp): the field's gain against depth in presses, near the contact and
// away from it.
#include <catch2/catch.hpp>

#include "core/loop/fingerprint_load_stiffening.hpp"
#include "core/loop/fingerprint_spread_saturation.hpp"
#include "tests/evidence_fixtures.hpp"

namespace test_fingerprint_load_stiffening {

using sb::Vec2;
using namespace sbtest;

namespace {

constexpr double kBeta = 500;        // 1/m: the field 1/1.5 as large at 1 mm
constexpr double kAmpPxPerM = 3000;  // the model's field: 3 px at 1 mm
constexpr double kNoisePx = 0.02;
// 1/g = 1 + beta delta exactly; the noise on ~3 px fields moves each per-sample beta by ~1 %: 10 % covers it.
constexpr double kBetaRelTol = 0.10;

// Presses to 1 mm at the grid centre (slightly off it per sample, so the samples differ); meas from pred.
sb::EvidenceSplit presses(const MeasOf& meas, std::uint64_t seed) {
  const auto frames = [](int i) { return press_frames(grid_centre() + Vec2(3.0 * i, 0), 1e-3); };
  const auto pred = [](int, const FrameSpec& f, std::size_t j) {
    return press_field(evidence_sensor().markers_rest_px[j], f.centre_px, kAmpPxPerM * f.depth_m, Vec2::Zero());
  };
  return make_split(6, frames, pred, meas, kNoisePx, seed);
}

// The gel stiffens: every marker scaled by 1 / (1 + beta delta).
Vec2 stiffened(int, const FrameSpec& f, std::size_t, const Vec2& p) { return p / (1 + kBeta * f.depth_m); }
// A contact-form error: only the near part (|pred| >= half the peak: at the Gaussian's flank, 0.5-1.5 widths out)
// loses gain with depth, the far part keeps it.
Vec2 near_only(int, const FrameSpec& f, std::size_t, const Vec2& p) {
  const double peak = kAmpPxPerM * f.depth_m * std::exp(-0.5);  // the profile's largest: at r = w
  return p.norm() >= 0.5 * peak ? Vec2(p / (1 + kBeta * f.depth_m)) : p;
}
Vec2 unchanged(int, const FrameSpec&, std::size_t, const Vec2& p) { return p; }

double fitted_beta(const std::string& n) { return n == "beta_per_m" ? kBeta : 0.0; }
double fitted_gain(const std::string& n) { return n == "gain_px" ? 1.0 : 0.0; }

}  // namespace

TEST_CASE("load_stiffening evidence: a uniform fall of the gain with depth is found", "[evidence][load_stiffening]") {
  const auto e =
      sb::load_stiffening_evidence(evidence_sensor(), presses(stiffened, 1), presses(stiffened, 2), fitted_beta);
  INFO(e.verdict);
  CHECK(e.found);
  CHECK(std::abs(e.calibration.estimate - kBeta) <= kBetaRelTol * kBeta);
  CHECK(std::abs(e.validation.estimate - kBeta) <= kBetaRelTol * kBeta);
}

TEST_CASE("load_stiffening evidence: an unchanged gain is not found", "[evidence][load_stiffening]") {
  const auto e =
      sb::load_stiffening_evidence(evidence_sensor(), presses(unchanged, 3), presses(unchanged, 4), fitted_beta);
  INFO(e.verdict);
  CHECK_FALSE(e.found);
}

// The whole field's beta is positive (the near part's fall), but the far part's is 0: the shape changed.
TEST_CASE("load_stiffening evidence: a fall near the contact only is a contact-form error",
          "[evidence][load_stiffening]") {
  const auto e =
      sb::load_stiffening_evidence(evidence_sensor(), presses(near_only, 5), presses(near_only, 6), fitted_beta);
  INFO(e.verdict);
  CHECK_FALSE(e.found);
  CHECK(e.calibration.estimate > 0);
  CHECK_THAT(e.verdict, Catch::Contains("does not fall alike"));
}

// Saturation is the near part falling faster than the far: found on near_only, not on a uniform stiffening
// (beta_near - beta_far = 0 within noise).
TEST_CASE("spread_saturation evidence: the near field's fall beyond the far field's", "[evidence][spread_saturation]") {
  const auto found =
      sb::spread_saturation_evidence(evidence_sensor(), presses(near_only, 7), presses(near_only, 8), fitted_gain);
  INFO(found.verdict);
  CHECK(found.found);
  CHECK(found.calibration.estimate > 0.5 * kBeta);
  const auto uniform =
      sb::spread_saturation_evidence(evidence_sensor(), presses(stiffened, 9), presses(stiffened, 10), fitted_gain);
  INFO(uniform.verdict);
  CHECK_FALSE(uniform.found);
}

}  // namespace test_fingerprint_load_stiffening
