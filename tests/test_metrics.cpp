#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "core/calibration/metrics.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_metrics {

using namespace sb;

namespace {
constexpr double kTol = 1e-12;  // a handful of double operations on O(1) numbers
const double kNaN = std::nan("");
}  // namespace

TEST_CASE("metrics: RMSE and CS on a hand-made two-marker frame", "[metrics]") {
  // Marker 0: meas (3, 4) (|m| = 5), pred (3, 0): error (0, -4), |e|^2 = 16, cos = 9 / (3 * 5) = 0.6.
  // Marker 1: meas (0, 0.2) (below 0.5 px: in the RMSE, not in the CS), pred (0, 0): |e|^2 = 0.04.
  // RMSE = sqrt((16 + 0.04) / 2) = sqrt(8.02); CS = 0.6 over one marker-frame.
  MetricsAccumulator acc;
  acc.add_frame({Vec2(3, 0), Vec2(0, 0)}, {Vec2(3, 4), Vec2(0, 0.2)});
  const MetricsResult r = acc.result();
  CHECK(r.n == 2);
  CHECK(r.n_cs == 1);
  CHECK(std::abs(r.rmse_px - std::sqrt(8.02)) < kTol);
  CHECK(std::abs(r.cs - 0.6) < kTol);
}

TEST_CASE("metrics: frames where nothing moves 0.5 px are skipped, NaN markers ignored", "[metrics]") {
  MetricsAccumulator acc;
  // Frame A: the largest measured motion is 0.49 px: not counted, however wrong the prediction.
  acc.add_frame({Vec2(100, 0), Vec2(0, 100)}, {Vec2(0.49, 0), Vec2(0, 0.1)});
  CHECK(acc.result().n == 0);
  CHECK(std::isnan(acc.result().rmse_px));
  CHECK(acc.frames_counted() == 0);
  // Frame B: marker 0 lost (NaN): skipped; marker 1 meas (0, 2), pred (0, -2): |e|^2 = 16, cos = -1.
  acc.add_frame({Vec2(5, 5), Vec2(0, -2)}, {Vec2(kNaN, kNaN), Vec2(0, 2)});
  const MetricsResult r = acc.result();
  CHECK(r.n == 1);
  CHECK(std::abs(r.rmse_px - 4.0) < kTol);
  CHECK(std::abs(r.cs + 1.0) < kTol);
  CHECK(acc.frames_counted() == 1);
}

TEST_CASE("metrics: a zero prediction counts 0 in the CS", "[metrics]") {
  // meas (1, 0) and (0, 1); pred (0, 0) and (0, 3): cosines 0 (zero prediction) and 1: CS = 0.5.
  // RMSE = sqrt((1 + 4) / 2).
  const MetricsResult r = frame_metrics({Vec2(0, 0), Vec2(0, 3)}, {Vec2(1, 0), Vec2(0, 1)});
  CHECK(r.n_cs == 2);
  CHECK(std::abs(r.cs - 0.5) < kTol);
  CHECK(std::abs(r.rmse_px - std::sqrt(2.5)) < kTol);
}

TEST_CASE("metrics: merged accumulators equal one accumulator over all frames", "[metrics]") {
  // Frame 1: meas (1, 0), pred (2, 0): |e|^2 = 1, cos 1. Frame 2: meas (0, 2), pred (0, 0): |e|^2 = 4,
  // cos 0. Merged: RMSE = sqrt(5 / 2), CS = 0.5, n = 2.
  MetricsAccumulator a, b, all;
  a.add_frame({Vec2(2, 0)}, {Vec2(1, 0)});
  b.add_frame({Vec2(0, 0)}, {Vec2(0, 2)});
  all.add_frame({Vec2(2, 0)}, {Vec2(1, 0)});
  all.add_frame({Vec2(0, 0)}, {Vec2(0, 2)});
  a.merge(b);
  CHECK(a.result().n == 2);
  CHECK(std::abs(a.result().rmse_px - std::sqrt(2.5)) < kTol);
  CHECK(std::abs(a.result().cs - 0.5) < kTol);
  CHECK(std::abs(a.result().rmse_px - all.result().rmse_px) < kTol);

  MotionMetrics mm;
  mm.add("shear", a);
  mm.add("twist", b);
  // Overall = a (2 marker-frames) + b (1): |e|^2 sum 1 + 4 + 4 = 9 over 3: RMSE sqrt(3).
  CHECK(mm.overall.result().n == 3);
  CHECK(std::abs(mm.overall.result().rmse_px - std::sqrt(3.0)) < kTol);
  CHECK(mm.per_motion.at("twist").result().n == 1);
}

TEST_CASE("metrics: mismatched field sizes are rejected", "[metrics]") {
  MetricsAccumulator acc;
  CHECK_THROWS_AS(acc.add_frame({Vec2(0, 0)}, {Vec2(1, 0), Vec2(0, 1)}), std::invalid_argument);
}

TEST_CASE("nothing_tracked: every marker lost, and only that", "[metrics]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK(sb::nothing_tracked({sb::Vec2(nan, nan), sb::Vec2(nan, nan)}));
  CHECK_FALSE(sb::nothing_tracked({sb::Vec2(nan, nan), sb::Vec2(0, 0)}));  // one marker kept, at rest
  CHECK_FALSE(sb::nothing_tracked({}));                                    // no row at all: not this case
}

}  // namespace test_metrics
