#pragma once
// The workbench's field export: every shown model, at its parameters, run afresh along the session's
// pose path and written as <dir>/<model id>/ (tsd/1, core/calibration/prediction_export). It runs on a worker
// thread (FieldExportJob) so a long replay does not freeze the window: the UI polls a status copy and
// may cancel while the fields are computed. All fields are computed before the first file is written,
// so a cancelled or failed export leaves the folder as it was; the writes themselves are atomic per
// file and are not interrupted. GL-free, tested in tests/test_field_export.cpp.
#include <atomic>
#include <memory>
#include <string>
#include <vector>

#include "core/base/params.hpp"
#include "core/base/progress.hpp"
#include "core/base/status_job.hpp"
#include "core/geometry/pose.hpp"

namespace sb {

struct Sensor;
struct Indenter;

struct FieldExportModel {
  std::string id;  // make_model id
  ParamSet params;
};

struct FieldExportRequest {
  std::string dir;    // target folder; <dir>/<id>/ per model
  std::string title;  // the session's title (dataset names and provenance)
  std::string sample_id = "path";
  std::shared_ptr<const Sensor> sensor;
  std::shared_ptr<const Indenter> indenter;
  std::vector<FieldExportModel> models;
  std::vector<Pose> path;  // X_EI per step
  double dt_s = 0.02;
};

// Throws InputError (naming the folder) when there is nothing to export, or when a model's target
// folder exists and is not an earlier shearbench field export: a user's data is never overwritten.
void check_export_target(const FieldExportRequest& req);

// check_export_target, then every model's field (progress: stage = model id, fraction of all steps;
// throws Cancelled before anything is written), then the writes. Returns the number of datasets written.
int export_fields(const FieldExportRequest& req, const Progress& progress = {});

struct FieldExportStatus {
  enum class Phase { kIdle, kRunning, kDone, kCancelled, kFailed } phase = Phase::kIdle;
  std::string stage;    // model being computed, or "writing"
  double fraction = 0;  // of all models' steps
  int written = 0;      // Done: datasets written
  std::string dir;      // the request's folder
  std::string error;    // Failed: why
  bool running() const { return phase == Phase::kRunning; }
};

class FieldExportJob {
 public:
  void start(FieldExportRequest request);  // cancels a running export first
  void cancel() { job_.cancel(); }
  FieldExportStatus status() const { return job_.status(); }  // a copy
  void wait() const { job_.wait(); }                          // blocks until not running (tests, headless renders)

 private:
  using Job = StatusJob<FieldExportStatus>;
  static void run(const FieldExportRequest& req, const std::atomic<bool>& cancel, Job& job);
  Job job_;
};

}  // namespace sb
