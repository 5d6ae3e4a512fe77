// core/rmse_series: the workbench's RMSE-over-time plot data.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <thread>

#include "core/calibration/rmse_series.hpp"
#include "tests/model_fixtures.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_rmse_series {

namespace {

constexpr double kRmseTol = 1e-12;
constexpr double kFarAboveM = 10e-3;  // a 2 mm sphere 10 mm above the gel: every model predicts zero

std::vector<sb::Pose> far_path(int n) {
  return std::vector<sb::Pose>(n, sb::make_pose(sb::Vec3(0, 0, kFarAboveM), sb::Quat::Identity()));
}

}  // namespace

TEST_CASE("with no contact the RMSE of a frame is the measured field's RMS", "[rmse_series]") {
  // Predictions are zero, so |pred - meas| = |meas|. Frame 0: every marker measured (3, 4) px -> RMSE 5.
  // Frame 1: nothing moves (below the 0.5 px motion threshold) -> the frame does not count: NaN.
  // Frame 2: one marker (6, 8) px, one lost (NaN), the rest 0 -> sqrt(100 / 62) over the 62 measured.
  auto sensor = sbtest::test_sensor();
  const std::size_t M = sensor->markers_rest_px.size();
  std::vector<std::vector<sb::Vec2>> meas(3, std::vector<sb::Vec2>(M, sb::Vec2::Zero()));
  for (auto& d : meas[0]) d = sb::Vec2(3, 4);
  for (auto& d : meas[1]) d = sb::Vec2(0.1, 0);
  meas[2][5] = sb::Vec2(6, 8);
  meas[2][6] = sb::Vec2(NAN, NAN);
  for (const auto& id : sb::model_ids()) {
    auto model = sb::make_model(id, sensor, sbtest::sphere_indenter(2e-3));
    const auto rmse = sb::rmse_over_time(*model, far_path(3), 0.02, meas);
    INFO(id);
    REQUIRE(rmse.size() == 3);
    CHECK(rmse[0] == Approx(5.0).margin(kRmseTol));
    CHECK(std::isnan(rmse[1]));
    CHECK(rmse[2] == Approx(std::sqrt(100.0 / 62.0)).margin(kRmseTol));
  }
}

TEST_CASE("a field already computed: its RMSE per frame against the measurement, to the shorter of the two",
          "[rmse_series]") {
  // Two markers. Frame 0: field (1, 0) and (0, 0) against measured (1, 3) and (0, 4): errors 3 and 4 px,
  // RMSE sqrt((9 + 16) / 2) = sqrt(12.5). Frame 1: nothing measured moves (0.1 px < the 0.5 px threshold): NaN.
  // The measurement has a third frame the field lacks: two values.
  const std::vector<std::vector<sb::Vec2>> field = {{sb::Vec2(1, 0), sb::Vec2(0, 0)}, {sb::Vec2(5, 5), sb::Vec2(5, 5)}};
  const std::vector<std::vector<sb::Vec2>> meas = {
      {sb::Vec2(1, 3), sb::Vec2(0, 4)}, {sb::Vec2(0.1, 0), sb::Vec2(0, 0.1)}, {sb::Vec2(9, 9), sb::Vec2(9, 9)}};
  const auto rmse = sb::rmse_of_fields(field, meas);
  REQUIRE(rmse.size() == 2);
  CHECK(rmse[0] == Approx(std::sqrt(12.5)).margin(kRmseTol));
  CHECK(std::isnan(rmse[1]));
}

TEST_CASE("the series job runs off the caller's thread and keeps the latest request", "[rmse_series]") {
  auto sensor = sbtest::test_sensor();
  const std::size_t M = sensor->markers_rest_px.size();
  sb::RmseSeriesRequest req;
  req.model_ids = {"tacsl", "hydroshear"};
  for (const auto& id : req.model_ids) req.params.push_back(sb::default_params(id));
  req.sensor = sensor;
  req.indenter = sbtest::sphere_indenter(2e-3);
  req.path = far_path(4);
  req.measured_px.assign(4, std::vector<sb::Vec2>(M, sb::Vec2(3, 4)));
  sb::RmseSeriesJob job;
  job.start(req);
  req.measured_px.assign(4, std::vector<sb::Vec2>(M, sb::Vec2(0, 2)));  // a second request replaces the first
  job.start(req);
  for (int i = 0; i < 500 && job.running(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  REQUIRE_FALSE(job.running());
  std::uint64_t generation = 0;
  const auto series = job.result(&generation);
  CHECK(generation == job.started());
  REQUIRE(series.size() == 2);
  for (const auto& s : series) {
    REQUIRE(s.size() == 4);
    for (double r : s) CHECK(r == Approx(2.0).margin(kRmseTol));
  }
}

}  // namespace test_rmse_series
