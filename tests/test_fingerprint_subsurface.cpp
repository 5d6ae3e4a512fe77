// The subsurface fingerprint (core/loop/fingerprint_subsurface.hpp): marker depth from the fine-scale content
// of the measured field against the model's, and the tracker noise it is judged against.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "core/loop/fingerprints.hpp"
#include "tests/fingerprint_series.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_fingerprint_subsurface {

using fingerprint_series::add_noise;
using fingerprint_series::apply_effect;
using fingerprint_series::sensor;
using fingerprint_series::Series;
using sb::FingerprintSample;
using sb::Vec2;

namespace {

// A field with fine structure on the grid: two sharp bumps (peak at 0.9 pitch) that grow over 10 frames.
FingerprintSample sharp_field() {
  FingerprintSample s;
  const auto& m = sensor().markers_rest_px;
  for (int k = 1; k <= 10; ++k) {
    std::vector<Vec2> f(m.size());
    for (std::size_t j = 0; j < m.size(); ++j) {
      f[j] = Vec2::Zero();
      for (const auto& [c, dir] :
           {std::pair{Vec2(126.5, 86.5), Vec2(1.0, 0.3)}, {Vec2(225.5, 152.5), Vec2(-0.4, 1.0)}}) {
        const double sc = (m[j] - c).norm() / 30.0;
        f[j] += 4.0 * k / 10.0 * std::exp(-0.5 * sc * sc) * dir;
      }
    }
    s.meas_px.push_back(f);
    s.pred_px.push_back(f);
    s.in_contact.push_back(1);
    s.held.push_back(0);
  }
  return s;
}

}  // namespace

TEST_CASE("subsurface fingerprint: depth from the fine-scale content against the model's", "[fingerprints]") {
  // The grid Laplacian by hand: one marker of an interior 4-neighbourhood moved by (1, 0), the rest still:
  // that marker contributes |0 - 1|^2 = 1 and each of its 4 interior neighbours |1/4 - 0|^2 = 1/16 (marker 31 is
  // the middle of the 7 x 9 grid, its neighbours 22, 30, 32, 40 are all interior).
  std::vector<Vec2> one(sensor().markers_rest_px.size(), Vec2::Zero());
  one[31] = Vec2(1, 0);
  CHECK(sb::grid_laplacian_energy(sensor(), one) == Approx(1.0 + 4.0 / 16.0));

  // Markers 1 mm deep (the effect: Gaussian smoothing, sigma 1 mm over a 2.09 mm pitch), exact model: the
  // Laplacians match exactly at 1 mm, so the depth comes back to the search's resolution (golden section to
  // 1e-7 m after a 0.1 mm scan); 2 % leaves room for a flat minimum.
  constexpr double kExactModelTol = 0.02;
  FingerprintSample s = sharp_field();
  s.meas_px = apply_effect("subsurface_markers", {{"depth_m", 0.001}}, s.meas_px, 0.02);
  const auto exact = sb::subsurface_fingerprint(sensor(), {s});
  INFO("depth " << exact.depth_m);
  CHECK(std::abs(exact.depth_m - 0.001) < kExactModelTol * 0.001);
  CHECK(exact.measured_fine_fraction < exact.model_fine_fraction);

  SECTION("not fooled by a smooth model-form error or a gain") {
    // The model is 30 % too strong (the match is up to a gain: attenuation and the model's stiffness drop
    // out) and wrong by a broad 1 px bump concentrated on the contact (sigma 4 mm = 63 px). The bump is not
    // free of fine-scale content on a 2.09 mm grid (its Laplacian over one pitch is ~ (33/63)^2 ~ 27 % of
    // its height), which reads as shallower markers: without noise the depth comes back at 0.912 mm
    // (-8.8 %); the 0.05 px noise spreads it by +-4 % (30 seeds: 0.874 .. 0.953 mm). Depth within 15 %.
    constexpr double kModelErrorTol = 0.15;
    FingerprintSample w = s;
    const auto& m = sensor().markers_rest_px;
    for (std::size_t k = 0; k < w.pred_px.size(); ++k)
      for (std::size_t j = 0; j < m.size(); ++j) {
        const double sc = (m[j] - Vec2(126.5, 86.5)).norm() / 63.0;
        w.pred_px[k][j] = 1.3 * w.pred_px[k][j] + (k + 1) / 10.0 * std::exp(-0.5 * sc * sc) * Vec2(1.0, 0.0);
      }
    add_noise(&w.meas_px, 0.05, 11);
    const auto f = sb::subsurface_fingerprint(sensor(), {w});
    INFO("depth " << f.depth_m);
    CHECK(std::abs(f.depth_m - 0.001) < kModelErrorTol * 0.001);
  }

  SECTION("markers on the surface: no depth") {
    const FingerprintSample surface = sharp_field();
    const auto f = sb::subsurface_fingerprint(sensor(), {surface});
    CHECK(f.depth_m < 0.25 * 2.0922e-3);  // below a quarter pitch: the finding's floor
    CHECK_FALSE(sb::fingerprint_check("subsurface_markers", sensor(), {surface}, {surface})->consistent);
  }
}

TEST_CASE("tracker noise from the measured series alone", "[fingerprints]") {
  // Markers on a straight ramp in time (x_k = 0.3 k px, y_k = -0.1 k px): the second difference
  // x_{k+1} - 2 x_k + x_{k-1} of the motion is exactly 0, so all of it is noise, N(0, 6 sigma^2); the
  // median of its |.| over 0.6745 sqrt(6) gives sigma back. 20 frames x 63 markers x 2 = 2268 values: the
  // median's relative standard error is about 1.25 / sqrt(2268) = 2.6 %; within 10 %.
  constexpr double kSigma = 0.05, kNoiseTol = 0.10;
  const std::size_t M = sensor().markers_rest_px.size();
  FingerprintSample s;
  for (int k = 0; k < 20; ++k) s.meas_px.emplace_back(M, Vec2(0.3 * k, -0.1 * k));
  const FingerprintSample clean = s;
  add_noise(&s.meas_px, kSigma, 5);
  CHECK(sb::tracker_noise_px({s}) == Approx(kSigma).epsilon(kNoiseTol));
  CHECK(sb::tracker_noise_px({clean}) == Approx(0.0).margin(1e-12));

  SECTION("a slip jump and lost markers do not move it") {
    // Every marker jumps 3 px along x between frames 9 and 10 (a slip): 2 of each marker's 36 second
    // differences carry +-3 px. With 5.6 % of the values outliers, the median of |.| moves to the
    // 0.5 / 0.944 = 53rd percentile of the noise's: Phi^-1(0.765) = 0.722 against 0.6745, +7 %. Within 20 %.
    // A lost marker (NaN) is skipped.
    constexpr double kJumpTol = 0.20;
    FingerprintSample j = s;
    for (int k = 10; k < 20; ++k)
      for (auto& d : j.meas_px[static_cast<std::size_t>(k)]) d += Vec2(3.0, 0.0);
    j.meas_px[4][7] = Vec2(std::nan(""), std::nan(""));
    CHECK(sb::tracker_noise_px({j}) == Approx(kSigma).epsilon(kJumpTol));
  }
  CHECK(std::isnan(sb::tracker_noise_px({})));
}

TEST_CASE("subsurface fingerprint: a depth counts only where the model explains the grid scale to noise",
          "[fingerprints]") {
  // Markers 1 mm deep seen through the exact model, with 0.05 px tracker noise: the smoothed model leaves
  // only the noise at the grid scale (misfit / noise ~ 1, rule <= 4), so the depth is found on both splits.
  FingerprintSample s = sharp_field();
  s.meas_px = apply_effect("subsurface_markers", {{"depth_m", 0.001}}, s.meas_px, 0.02);
  FingerprintSample cal = s, val = s;
  add_noise(&cal.meas_px, 0.05, 21);
  add_noise(&val.meas_px, 0.05, 22);
  const auto exact = sb::fingerprint_check("subsurface_markers", sensor(), {cal}, {val});
  INFO(exact->verdict);
  CHECK(exact->consistent);
  CHECK(exact->calibration == Approx(0.001).epsilon(0.15));

  // The same model against a gel with a feature at the grid scale that the model lacks (as a stick zone's
  // edge would be): a bump of sigma 1 mm (16 px) on the middle marker (31) of the measurement, growing to 3 px
  // at the last frame (the field peaks at 4 px). Its neighbours, one pitch (33 px) away, see
  // exp(-33^2 / 2 / 16^2) = 0.12 of it: its grid Laplacian energy is about 0.86 x 9 = 7.7 px^2 at the last
  // frame and 7.7 x 3.85 = 30 px^2 over the ramp (sum of ((k + 1) / 10)^2), against the noise's
  // 0.05^2 x 787.5 (components x (1 + 1/4)) = 2.0 px^2: 15x once a depth has taken what it can (rule 4x).
  // A model sharper than the gel is the other way round: smoothing it removes its error too, which is why that
  // case reads as depth at all. The depth read here is still right (1.02 mm); the check declines it because
  // nothing says the model's form is right, and the report says why.
  const auto& m = sensor().markers_rest_px;
  for (auto* w : {&cal, &val})
    for (std::size_t k = 0; k < w->meas_px.size(); ++k)
      for (std::size_t j = 0; j < m.size(); ++j) {
        const double sc = (m[j] - m[31]).norm() / 16.0;
        w->meas_px[k][j] += 3.0 * (k + 1) / 10.0 * std::exp(-0.5 * sc * sc) * Vec2(0.0, 1.0);
      }
  const auto wrong = sb::fingerprint_check("subsurface_markers", sensor(), {cal}, {val});
  INFO(wrong->verdict);
  CHECK_FALSE(wrong->consistent);
  CHECK(wrong->verdict.find("wrong at the grid scale") != std::string::npos);

  SECTION("single frames (a photo per sample) give no noise to judge by") {
    // The FOTS press/shear pair has one frame per sample: no second difference in time, no noise estimate,
    // and a depth read against the model cannot be told from its form.
    FingerprintSample one = s;
    one.meas_px = {s.meas_px.back()};
    one.pred_px = {s.pred_px.back()};
    one.in_contact = {1};
    one.held = {0};
    const auto single = sb::fingerprint_check("subsurface_markers", sensor(), {one}, {one});
    INFO(single->verdict);
    CHECK_FALSE(single->consistent);
    CHECK(single->verdict.find("no tracker noise") != std::string::npos);
  }
}

}  // namespace test_fingerprint_subsurface
