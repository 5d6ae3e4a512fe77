// core/fit_job: the fit panel's worker.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>

#include "core/base/data_root.hpp"
#include "core/calibration/fit_job.hpp"
#include "core/models/model.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_fit_job {

namespace {

std::string data_root() {
  const char* env = std::getenv("SHEARBENCH_DATA");
  return env ? env : sb::resolve_data_root("");
}

sb::FitJobRequest tacsl_request() {
  sb::FitJobRequest r;
  r.data_root = data_root();
  r.dataset_dir = data_root() + "/twin/twin_sphere8";
  if (!std::filesystem::is_directory(r.dataset_dir)) FAIL("needs the dataset " << r.dataset_dir);
  r.model_id = "tacsl";
  r.start = sb::default_params("tacsl");
  r.max_iterations = 3;
  return r;
}

}  // namespace

TEST_CASE("a fit on the worker thread finishes with a result no worse than its start", "[fit_job]") {
  // Least squares from `start`: the fit keeps the best point it evaluates, and `start` is one of them,
  // so the calibration RMSE after is at most the one before (up to rounding).
  constexpr double kRmseSlackPx = 1e-9;
  sb::FitJob job;
  job.start(tacsl_request());
  job.wait();
  const sb::FitJobStatus s = job.status();
  REQUIRE(s.phase == sb::FitJobStatus::Phase::kDone);
  REQUIRE(s.result.has_value());
  CHECK_FALSE(s.losses.empty());
  CHECK(s.calibration_rmse_after_px <= s.calibration_rmse_before_px + kRmseSlackPx);
  CHECK(s.result->params.size() == sb::default_params("tacsl").size());
}

TEST_CASE("the fit panel's dataset field takes a data: path", "[fit_job]") {
  // What a user types in the panel (and the CLI takes): data:twin/twin_sphere8 names the data root's folder.
  sb::FitJobRequest r = tacsl_request();
  r.dataset_dir = "data:twin/twin_sphere8";
  r.max_iterations = 1;
  sb::FitJob job;
  job.start(r);
  job.wait();
  const sb::FitJobStatus s = job.status();
  INFO(s.error);
  CHECK(s.phase == sb::FitJobStatus::Phase::kDone);
}

TEST_CASE("a cancelled fit says so and a bad dataset fails with its path", "[fit_job]") {
  sb::FitJob job;
  job.start(tacsl_request());
  job.cancel();
  job.wait();
  const auto phase = job.status().phase;
  // Cancelled before or during the first stage; the fit never reports Done after a cancel.
  CHECK(phase == sb::FitJobStatus::Phase::kCancelled);

  sb::FitJobRequest bad = tacsl_request();
  bad.dataset_dir = "/nonexistent/dataset";
  job.start(bad);
  job.wait();
  const sb::FitJobStatus s = job.status();
  CHECK(s.phase == sb::FitJobStatus::Phase::kFailed);
  CHECK_THAT(s.error, Catch::Contains("/nonexistent/dataset"));
}

}  // namespace test_fit_job
