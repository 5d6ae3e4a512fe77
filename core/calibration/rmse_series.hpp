#pragma once
// RMSE over time: every model's per-frame RMSE (core/calibration/metrics.hpp frame_metrics) against the measured
// field over a whole replay, for the workbench's plots. Computed on a worker thread from fresh models
// (never the workbench's own, which the physics thread owns), so the UI never waits; a new request
// (parameters changed) cancels the running one.
#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "core/models/model.hpp"

namespace sb {

// Steps `model` (reset first) through path[0..n) with n = min(path, measured) and returns frame k's RMSE
// (px), NaN where the frame does not count (nothing measured moves). Stops early (shorter result)
// when `cancel` is set.
std::vector<double> rmse_over_time(ShearModel& model, const std::vector<Pose>& path, double dt_s,
                                   const std::vector<std::vector<Vec2>>& measured_px,
                                   const std::atomic<bool>* cancel = nullptr);

// Frame k's RMSE (px) of fields[k] against measured_px[k] for k < min(sizes), NaN where the frame does not count:
// rmse_over_time's series for a field already computed (the residual loop's answer, core/workbench).
std::vector<double> rmse_of_fields(const std::vector<std::vector<Vec2>>& fields,
                                   const std::vector<std::vector<Vec2>>& measured_px);

struct RmseSeriesRequest {
  std::vector<std::string> model_ids;
  std::vector<ParamSet> params;  // per model
  std::shared_ptr<const Sensor> sensor;
  std::shared_ptr<const Indenter> indenter;
  std::vector<Pose> path;
  double dt_s = 0.02;
  std::vector<std::vector<Vec2>> measured_px;
};

class RmseSeriesJob {
 public:
  ~RmseSeriesJob();
  void start(RmseSeriesRequest request);  // cancels and replaces a running job
  bool running() const { return running_.load(); }
  // The finished series (one per model) and the generation it belongs to; empty until the first finishes.
  std::vector<std::vector<double>> result(std::uint64_t* generation = nullptr) const;
  std::uint64_t started() const { return generation_; }

 private:
  void stop();
  std::thread worker_;
  std::atomic<bool> cancel_{false};
  std::atomic<bool> running_{false};
  mutable std::mutex mutex_;
  std::vector<std::vector<double>> result_;
  std::uint64_t generation_ = 0;
  std::uint64_t result_generation_ = 0;
};

}  // namespace sb
