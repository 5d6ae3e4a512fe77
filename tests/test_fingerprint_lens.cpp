// The lens fingerprint (core/loop/fingerprint_lens.hpp): k1 from the rest grid on a lattice, else from the
// residual that is not symmetric about the contact, through a symmetric model-form error.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "core/loop/fingerprints.hpp"
#include "core/loop/rest_grid_lens.hpp"
#include "tests/fingerprint_series.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_fingerprint_lens {

using fingerprint_series::add_noise;
using fingerprint_series::apply_effect;
using fingerprint_series::sensor;
using fingerprint_series::Series;
using sb::FingerprintSample;
using sb::Vec2;

namespace {

// A press and twist of an axisymmetric indenter at `centre_px`: the field is symmetric about the contact,
// radial part A s exp(1/2 - s^2/2) (s = rho / 40 px, peak A at 40 px) and tangential part B times the same
// profile, both growing over 12 frames.
FingerprintSample axisymmetric_press(const Vec2& centre_px, double A, double B, const sb::Sensor& on = sensor()) {
  FingerprintSample s;
  const auto& m = on.markers_rest_px;
  for (int k = 1; k <= 12; ++k) {
    std::vector<Vec2> f(m.size());
    for (std::size_t j = 0; j < m.size(); ++j) {
      const Vec2 out = m[j] - centre_px;
      const double rho = out.norm(), sc = rho / 40.0;
      const Vec2 radial = rho > 0 ? Vec2(out / rho) : Vec2(1, 0), tangential(-radial.y(), radial.x());
      const double profile = sc * std::exp(0.5 - 0.5 * sc * sc) * k / 12.0;
      f[j] = profile * (A * radial + B * tangential);
    }
    s.meas_px.push_back(f);
    s.pred_px.push_back(f);
    s.in_contact.push_back(1);
    s.held.push_back(0);
    s.contact_centre_px.push_back(centre_px);
    s.travel_px.push_back(0.0);
  }
  return s;
}

// The samples as a camera with lens k1 sees them (the effect on each frame); pred stays the undistorted field.
std::vector<FingerprintSample> through_lens(std::vector<FingerprintSample> samples, double k1,
                                            const sb::Sensor& on = sensor()) {
  for (auto& s : samples) s.meas_px = apply_effect("lens_distortion", {{"k1", k1}}, s.meas_px, 0.02, on);
  return samples;
}

// The default sensor with its rest grid no longer a lattice (each marker moved by up to a fifth of the pitch
// along a fixed pseudo-random direction; p_EM kept): the lens fingerprint falls back on the residual.
const sb::Sensor& scattered_sensor() {
  static const sb::Sensor s = [] {
    sb::Sensor out = sb::make_default_sensor();
    for (std::size_t j = 0; j < out.markers_rest_px.size(); ++j) {
      const double a = 2.399963 * double(j);  // the golden angle: no two directions alike
      out.markers_rest_px[j] += 6.6 * std::fmod(0.618034 * double(j), 1.0) * Vec2(std::cos(a), std::sin(a));
    }
    return out;
  }();
  return s;
}

// A contact model's error of a press: symmetric about the contact, 1 px radial, wider than the field
// (peak at 70 px), plus a uniform 0.3 px offset.
void add_symmetric_model_error(FingerprintSample* s) {
  const auto& m = sensor().markers_rest_px;
  for (std::size_t k = 0; k < s->pred_px.size(); ++k)
    for (std::size_t j = 0; j < m.size(); ++j) {
      const Vec2 out = m[j] - s->contact_centre_px[k];
      const double rho = out.norm(), sc = rho / 70.0;
      const Vec2 radial = rho > 0 ? Vec2(out / rho) : Vec2(1, 0);
      s->pred_px[k][j] += (k + 1) / 12.0 * (sc * std::exp(0.5 - 0.5 * sc * sc) * radial + Vec2(0.3, 0.0));
    }
}

}  // namespace

TEST_CASE("lens fingerprint: k1 from the residual that is not symmetric about the contact", "[fingerprints]") {
  // The pattern is the effect's k1 term: at rest m = (259.5, 119.5) (r = 100 / 200 = 0.5), a 10 px move along x
  // is seen as D(m + d) - D(m) = 10 + k1 (110^3 - 100^3) / 200^2 = 10 + 8.275 k1 px (the test of the effect).
  CHECK(sb::lens_k1_pattern(sensor().camera, Vec2(259.5, 119.5), Vec2(10, 0)).x() == Approx(8.275).epsilon(1e-12));
  // Two presses off the principal point (the lens's asymmetric part grows with the contact's distance from it).
  const std::vector<FingerprintSample> presses = {axisymmetric_press(Vec2(230, 80), 8.0, 0.0),
                                                  axisymmetric_press(Vec2(90, 160), 6.0, 3.0)};
  // Exact model, k1 = -0.15: the residual is k1 times the pattern of the model's field exactly (k2 = 0), and
  // projecting both on the same nuisance fields keeps that: k1 back to rounding.
  constexpr double kExactModelTol = 1e-9;
  const auto exact = sb::lens_fingerprint(sensor(), through_lens(presses, -0.15));
  INFO("k1 " << exact.k1 << " +- " << exact.k1_stderr << " signal " << exact.signal_rms_px << " px");
  CHECK(std::abs(exact.k1 + 0.15) < kExactModelTol * 0.15);
  CHECK(exact.frames == 24);

  SECTION("not fooled by a symmetric model-form error and noise") {
    // The model is wrong by a smooth, contact-centred field larger than the lens's whole effect (1 px against
    // 0.1-0.4 px) and the tracker adds 0.05 px: k1 within 10 % (the noise's share: stderr ~ 0.005).
    constexpr double kModelErrorTol = 0.10;
    auto seen = through_lens(presses, -0.15);
    std::uint64_t seed = 7;
    for (auto& s : seen) {
      add_symmetric_model_error(&s);
      add_noise(&s.meas_px, 0.05, seed++);
    }
    const auto f = sb::lens_fingerprint(sensor(), seen);
    INFO("k1 " << f.k1 << " +- " << f.k1_stderr);
    CHECK(std::abs(f.k1 + 0.15) < kModelErrorTol * 0.15);
    // The same model error without a lens reads as no lens.
    auto none = presses;
    for (auto& s : none) {
      add_symmetric_model_error(&s);
      add_noise(&s.meas_px, 0.05, seed++);
    }
    const auto z = sb::lens_fingerprint(sensor(), none);
    INFO("k1 without lens " << z.k1 << " +- " << z.k1_stderr);
    CHECK(std::abs(z.k1) < 0.02);
  }

  SECTION("a slide is not used: its field is not symmetric") {
    auto slid = through_lens(presses, -0.15);
    for (auto& s : slid)
      for (auto& t : s.travel_px) t = 5.0;
    CHECK(std::isnan(sb::lens_fingerprint(sensor(), slid).k1));
  }

  SECTION("on a rest grid that is not a lattice, the finding bounds k1 near its estimate and holds k2") {
    const sb::Sensor& on = scattered_sensor();
    REQUIRE(sb::fingerprint_needs_model("lens_distortion", on));
    const std::vector<FingerprintSample> scattered = {axisymmetric_press(Vec2(230, 80), 8.0, 0.0, on),
                                                      axisymmetric_press(Vec2(90, 160), 6.0, 3.0, on)};
    const auto seen = through_lens(scattered, -0.15, on);
    const auto check = sb::fingerprint_check("lens_distortion", on, seen, seen);
    INFO(check->evidence << ": " << check->verdict);
    REQUIRE(check->consistent);
    CHECK(std::abs(check->calibration + 0.15) < kExactModelTol * 0.15);
    CHECK(check->evidence.find("the rest grid is not a lattice") != std::string::npos);
    CHECK_FALSE(check->beyond_model_form);
    REQUIRE(check->band.size() == 1);
    CHECK(check->band[0].low == Approx(check->calibration * 1.5));  // k1 < 0: [1.5 k1, k1 / 1.5]
    CHECK(check->band[0].high == Approx(check->calibration / 1.5));
    REQUIRE(check->held.size() == 1);
    CHECK(check->held[0].first == "k2");
  }
}

TEST_CASE("lens fingerprint: a rest grid that is a lattice is the evidence, whatever the residual says",
          "[fingerprints]") {
  const std::vector<FingerprintSample> presses = {axisymmetric_press(Vec2(230, 80), 8.0, 0.0),
                                                  axisymmetric_press(Vec2(90, 160), 6.0, 3.0)};
  // The default sensor's rest grid is a perfect lattice: k1 = 0 there, so a lens the residual reads (-0.15
  // exactly, test above) is not found, and no model's field is needed.
  REQUIRE_FALSE(sb::fingerprint_needs_model("lens_distortion", sensor()));
  const auto seen = through_lens(presses, -0.15);
  const auto flat = sb::fingerprint_check("lens_distortion", sensor(), seen, seen);
  INFO(flat->verdict);
  CHECK_FALSE(flat->consistent);
  CHECK(flat->verdict.find("rest grid: a lattice of 63 markers") == 0);
  CHECK(flat->verdict.find("not found, k1 is none") != std::string::npos);

  // The rest grid as a lens with k1 = -0.15 images it (p_EM kept: the markers are where they are): found from
  // the rest positions alone (exact: to rounding), the same on both splits, held with k2 = 0, accepted on that
  // evidence; the residual of presses without any lens does not matter.
  sb::Sensor bent = sb::make_default_sensor();
  for (Vec2& m : bent.markers_rest_px) m = sb::lens_distort_px(bent.camera, -0.15, m);
  constexpr double kExactTol = 1e-9;
  const auto check = sb::fingerprint_check("lens_distortion", bent, presses, presses);
  INFO(check->verdict);
  REQUIRE(check->consistent);
  CHECK(check->beyond_model_form);
  CHECK(check->acceptance == sb::FingerprintCheck::Acceptance::kEvidence);
  CHECK(std::abs(check->calibration + 0.15) < kExactTol);
  CHECK(check->validation == check->calibration);
  CHECK(check->band.empty());
  REQUIRE(check->held.size() == 2);
  CHECK(check->held[0].first == "k1");
  CHECK(check->held[0].second == check->calibration);
  CHECK(check->held[1] == std::pair<std::string, double>("k2", 0.0));
  CHECK(check->evidence.find("rest grid") != std::string::npos);

  SECTION("a small lens within its noise is not found") {
    // k1 = 0.001 with 0.05 px noise on the rest grid: its standard error is 0.00035 (test_rest_grid_lens), so
    // the estimate is below both min_k1 (0.02) and 3 standard errors' worth of a finding.
    sb::Sensor faint = sb::make_default_sensor();
    std::vector<std::vector<Vec2>> rest{faint.markers_rest_px};
    for (Vec2& m : rest[0]) m = sb::lens_distort_px(faint.camera, 0.001, m);
    add_noise(&rest, 0.05, 99);
    faint.markers_rest_px = rest[0];
    const auto c = sb::fingerprint_check("lens_distortion", faint, presses, presses);
    INFO(c->verdict);
    CHECK_FALSE(c->consistent);
    CHECK(std::abs(c->calibration - 0.001) < 0.002);
  }
}

// ------------------------------------------------------------------------------------- subsurface

}  // namespace test_fingerprint_lens
