#include "core/calibration/fit_job.hpp"

#include <filesystem>

#include "core/base/data_root.hpp"
#include "core/base/free_memory.hpp"
#include "core/calibration/fit_data.hpp"
#include "core/data/tsd.hpp"

namespace sb {

void FitJob::start(FitJobRequest request) {
  FitJobStatus loading;
  loading.phase = FitJobStatus::Phase::kLoading;
  job_.start(std::move(loading),
             [req = std::move(request)](const std::atomic<bool>& cancel, Job& job) { run(req, cancel, job); });
}

void FitJob::run(const FitJobRequest& req, const std::atomic<bool>& cancel, Job& job) {
  try {
    Warnings warnings;
    // The panel's field takes what the CLI takes: "data:twin/..." or a folder (relative: the working directory).
    const std::string dir = resolve_path(req.dataset_dir, req.data_root, "");
    const Dataset ds = read_dataset(std::filesystem::absolute(dir).string(), &warnings);
    const FitData data = load_calibration_data(ds, req.data_root, &warnings);
    job.update([](FitJobStatus& s) { s.phase = FitJobStatus::Phase::kFitting; });
    FitOptions o;
    o.stages = req.stages;
    o.joint = req.joint;
    o.max_iterations = req.max_iterations;
    o.cancel = &cancel;
    o.progress = [&job](const FitProgress& p) {
      job.update([&](FitJobStatus& s) {
        s.stage = p.stage;
        s.iteration = p.iteration;
        append_stage_loss(s.losses, p.stage, p.loss);
      });
    };
    const double before = fit_rmse_px(req.model_id, data.sensor, data.samples, req.start);
    CalibrationResult r = fit_model(req.model_id, data.sensor, data.samples, req.start, o);
    const double after = r.cancelled ? before : fit_rmse_px(req.model_id, data.sensor, data.samples, r.params);
    job.update([&](FitJobStatus& s) {
      s.phase = r.cancelled ? FitJobStatus::Phase::kCancelled : FitJobStatus::Phase::kDone;
      s.calibration_rmse_before_px = before;
      s.calibration_rmse_after_px = after;
      s.result = std::move(r);
    });
  } catch (const std::exception& e) {
    job.update([&](FitJobStatus& s) {
      s.phase = FitJobStatus::Phase::kFailed;
      s.error = e.what();
    });
  }
  return_free_memory_to_os();  // the dataset and the fit's buffers are gone by here
}

}  // namespace sb
