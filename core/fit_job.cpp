#include "core/fit_job.hpp"

#include <chrono>
#include <filesystem>

#include "core/fit_data.hpp"
#include "core/tsd.hpp"

namespace sb {

FitJob::~FitJob() {
  cancel();
  if (worker_.joinable()) worker_.join();
}

void FitJob::cancel() { cancel_ = true; }

void FitJob::start(FitJobRequest request) {
  cancel();
  if (worker_.joinable()) worker_.join();
  cancel_ = false;
  set([](FitJobStatus& s) { s = FitJobStatus{}; s.phase = FitJobStatus::Phase::Loading; });
  worker_ = std::thread([this, req = std::move(request)] { run(req); });
}

void FitJob::set(const std::function<void(FitJobStatus&)>& edit) {
  std::lock_guard<std::mutex> lock(mutex_);
  edit(status_);
}

FitJobStatus FitJob::status() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return status_;
}

void FitJob::wait() const {
  while (status().running()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
}

void FitJob::run(const FitJobRequest& req) {
  try {
    Warnings warnings;
    const Dataset ds = read_dataset(std::filesystem::absolute(req.dataset_dir).string(), &warnings);
    const FitData data = load_calibration_data(ds, req.data_root, &warnings);
    set([](FitJobStatus& s) { s.phase = FitJobStatus::Phase::Fitting; });
    FitOptions o;
    o.stages = req.stages;
    o.joint = req.joint;
    o.max_iterations = req.max_iterations;
    o.cancel = &cancel_;
    o.progress = [this](const FitProgress& p) {
      set([&](FitJobStatus& s) {
        s.stage = p.stage;
        s.iteration = p.iteration;
        s.losses.push_back(static_cast<float>(p.loss));
      });
    };
    const double before = fit_rmse_px(req.model_id, data.sensor, data.samples, req.start);
    CalibrationResult r = fit_model(req.model_id, data.sensor, data.samples, req.start, o);
    const double after = r.cancelled ? before : fit_rmse_px(req.model_id, data.sensor, data.samples, r.params);
    set([&](FitJobStatus& s) {
      s.phase = r.cancelled ? FitJobStatus::Phase::Cancelled : FitJobStatus::Phase::Done;
      s.calibration_rmse_before_px = before;
      s.calibration_rmse_after_px = after;
      s.result = std::move(r);
    });
  } catch (const std::exception& e) {
    set([&](FitJobStatus& s) {
      s.phase = FitJobStatus::Phase::Failed;
      s.error = e.what();
    });
  }
}

}  // namespace sb
