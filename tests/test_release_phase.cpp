// The release phase of a pose-unknown recording and its recovery law (core/loop/release_phase.hpp).
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "core/loop/release_phase.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_release_phase {

using namespace sb;

namespace {

constexpr double kDt = 0.05;  // s per frame
constexpr int kMarkers = 12;
// tau is searched on a grid of 40 points per decade: a factor 10^(1/40) = 1.059 between neighbours, so
// the nearest grid point is within 3 % of any tau.
constexpr double kTauRelTol = 0.031;
constexpr double kTight = 1e-9;

// 20 loaded frames at 5 px, then `release` frames fading as d0 [c + (1 - c) exp(-t / tau)] from a
// unit field d0 (every marker 1 px, in different directions).
std::vector<std::vector<Vec2>> recording(int release, double tau, double c) {
  std::vector<std::vector<Vec2>> d;
  for (int k = 0; k < 20; ++k) {
    d.emplace_back();
    for (int i = 0; i < kMarkers; ++i) d.back().push_back(5.0 * Vec2(std::cos(0.5 * i), std::sin(0.5 * i)));
  }
  for (int k = 0; k < release; ++k) {
    const double g = c + (1 - c) * std::exp(-k * kDt / tau);
    d.emplace_back();
    for (int i = 0; i < kMarkers; ++i) d.back().push_back(g * Vec2(std::cos(0.5 * i), std::sin(0.5 * i)));
  }
  return d;
}

}  // namespace

TEST_CASE("release phase: found after the load, recovery law recovered, held-out error", "[release]") {
  const double tau = 0.5, c = 0.2;
  auto d = recording(40, tau, c);
  d[30][3] = Vec2(std::numeric_limits<double>::quiet_NaN(), 0.0);  // a lost marker is skipped
  const ReleasePhase r = analyse_release(d, kDt);
  REQUIRE(r.found);
  CHECK(r.peak_mean_px == Approx(5.0));
  // Frame 20 is the first below 30 % of 5 px (its mean |d| is 1 px).
  CHECK(r.release_frame == 20);
  CHECK(r.frames == 40);
  CHECK(r.left_mean_px == Approx(1.0));
  CHECK(r.left_max_px == Approx(1.0));
  CHECK(r.end_mean_px == Approx(c + (1 - c) * std::exp(-39 * kDt / tau)));
  CHECK(std::abs(r.fit.tau_s - tau) <= kTauRelTol * tau);
  CHECK_FALSE(r.fit.tau_at_bound);
  CHECK(r.fit.permanent == Approx(c).margin(0.02));
  // Held out: frames 20 + 1 + 19 = 40 .. 59. The zero field's RMSE is the RMS of g (|d0| = 1 px).
  double sum = 0;
  for (int k = 20; k < 40; ++k) sum += std::pow(c + (1 - c) * std::exp(-k * kDt / tau), 2);
  CHECK(r.heldout_rmse_zero_px == Approx(std::sqrt(sum / 20)).epsilon(0.01));  // one NaN marker-frame fewer
  CHECK(r.heldout_rmse_fit_px < 0.02);
  // Persistence (d = d0 throughout): RMS of 1 - g over the held-out frames.
  double sum_p = 0;
  for (int k = 20; k < 40; ++k) sum_p += std::pow(1 - (c + (1 - c) * std::exp(-k * kDt / tau)), 2);
  CHECK(r.heldout_rmse_persist_px == Approx(std::sqrt(sum_p / 20)).epsilon(0.01));
}

TEST_CASE("release phase: an exact law on the grid fits exactly; no decay hits the bound", "[release]") {
  // tau = 10^(k/40) on the grid from tau_min = dt: 0.05 * 10^(20/40) = 0.158 s.
  const double tau = kDt * std::pow(10.0, 0.5);
  const auto d = recording(30, tau, 0.0);
  const ReleaseFit f = fit_release(d, 20, 21, 50, kDt);
  CHECK(std::abs(f.tau_s - tau) < kTight * tau);
  CHECK(f.permanent < kTight);
  CHECK(release_rmse(d, 20, 21, 50, kDt, &f) < kTight);
  // A field that stays (no recovery at all): c = 1, and tau is meaningless (any tau fits).
  const auto flat = recording(30, 1.0, 1.0);
  const ReleaseFit g = fit_release(flat, 20, 21, 50, kDt);
  CHECK(g.permanent == Approx(1.0));
  CHECK(release_rmse(flat, 20, 21, 50, kDt, &g) < kTight);
}

TEST_CASE("release phase: none while still loaded, after a new contact, or when too short", "[release]") {
  auto loaded = recording(0, 1.0, 0.0);
  CHECK_FALSE(analyse_release(loaded, kDt).found);
  CHECK_THAT(analyse_release(loaded, kDt).why_not, Catch::Contains("still loaded"));
  auto again = recording(10, 0.2, 0.0);
  for (int k = 0; k < 5; ++k) again.push_back(loaded[0]);                                      // pressed again ...
  for (int k = 0; k < 10; ++k) again.push_back(std::vector<Vec2>(kMarkers, Vec2(0.01, 0.0)));  // ... and released
  // The last loaded frame is the second press's: the release after it is the one analysed.
  const ReleasePhase r = analyse_release(again, kDt);
  CHECK(r.found);
  CHECK(r.release_frame == 35);
  auto bump = recording(10, 0.2, 0.0);
  const double to_2px = 2.0 / bump[25][0].norm();  // every marker 2 px: above 30 % of 5 px, below 50 %
  for (auto& v : bump[25]) v *= to_2px;
  CHECK_THAT(analyse_release(bump, kDt).why_not, Catch::Contains("contact again"));
  CHECK_THAT(analyse_release(recording(3, 1.0, 0.0), kDt).why_not, Catch::Contains("only 3 frames"));
  // Still dropping fast (each frame keeps exp(-0.05 / 0.1) = 61 % < 80 % of the previous one): unloading,
  // not release, until the 0.01 px floor where the field settles.
  auto unloading = recording(6, 0.1, 0.0);
  for (int k = 0; k < 6; ++k) unloading.push_back(std::vector<Vec2>(kMarkers, Vec2(0.0, 0.01)));
  CHECK(analyse_release(unloading, kDt).release_frame == 26);
  CHECK_THAT(analyse_release({std::vector<Vec2>(kMarkers, Vec2::Zero())}, kDt).why_not,
             Catch::Contains("no marker moves"));
}

}  // namespace test_release_phase
