#pragma once
// A calibration fit on a worker thread, for the workbench's fit panel (MuJoCo-simulate style: the UI
// polls a status copy every frame and never waits; Cancel sets a flag the fit checks between Ceres
// iterations). GL-free, tested in tests/test_fit_job.cpp.
#include <atomic>
#include <optional>
#include <string>
#include <vector>

#include "core/base/status_job.hpp"
#include "core/calibration/fit.hpp"
#include "core/calibration/stage_losses.hpp"

namespace sb {

struct FitJobRequest {
  std::string dataset_dir;  // tsd/1 folder (its calibration split is fitted)
  std::string data_root;
  std::string model_id;
  ParamSet start;                   // the parameters the user has now
  std::vector<std::string> stages;  // empty: the model's whole table
  bool joint = true;                // stages, then the joint refinement: the best fit (false: the paper's stages only)
  int max_iterations = 30;
};

struct FitJobStatus {
  enum class Phase { kIdle, kLoading, kFitting, kDone, kCancelled, kFailed } phase = Phase::kIdle;
  std::string stage;  // current stage
  int iteration = 0;
  std::vector<StageLosses> losses;          // Ceres cost after every iteration reported, per stage run
  std::string error;                        // Failed: why
  std::optional<CalibrationResult> result;  // Done (and Cancelled: the completed stages)
  double calibration_rmse_before_px = 0, calibration_rmse_after_px = 0;  // RMSE over the calibration split
  bool running() const { return phase == Phase::kLoading || phase == Phase::kFitting; }
};

class FitJob {
 public:
  void start(FitJobRequest request);  // cancels a running fit first
  void cancel() { job_.cancel(); }
  FitJobStatus status() const { return job_.status(); }  // a copy
  void wait() const { job_.wait(); }                     // blocks until not running (tests, headless)

 private:
  using Job = StatusJob<FitJobStatus>;
  static void run(const FitJobRequest& req, const std::atomic<bool>& cancel, Job& job);
  Job job_;
};

}  // namespace sb
