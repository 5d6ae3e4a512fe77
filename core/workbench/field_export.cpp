#include "core/workbench/field_export.hpp"

#include <filesystem>

#include "core/base/error.hpp"
#include "core/calibration/prediction_export.hpp"
#include "core/data/json_read.hpp"
#include "core/effects/model_spec.hpp"
#include "core/models/model.hpp"

namespace fs = std::filesystem;

namespace sb {
namespace {

// An earlier export is recognised by its dataset.json's "shearbench": {"export": true}.
bool is_field_export(const fs::path& folder) {
  const fs::path json = folder / "dataset.json";
  if (!fs::exists(json)) return false;
  try {
    return jsonin::load_file(json.string()).value("shearbench", nlohmann::json::object()).value("export", false);
  } catch (const std::exception&) {
    return false;
  }
}

PredictionExport describe(const FieldExportRequest& req, const FieldExportModel& m) {
  PredictionExport e;
  e.name = req.title + " " + m.id;
  e.sample_id = req.sample_id;
  e.provenance = "shearbench " SHEARBENCH_VERSION " workbench field export: model " + m.id + ", params " +
                 m.params.to_json().dump() + ", the session's pose path (" + std::to_string(req.path.size()) +
                 " poses) of " + req.title;
  e.shearbench = {{"export", true}, {"model", m.id}, {"params", m.params.to_json()}};
  e.sensor = req.sensor;
  e.indenter = req.indenter;
  e.dt_s = req.dt_s;
  e.X_EI = req.path;
  return e;
}

}  // namespace

void check_export_target(const FieldExportRequest& req) {
  if (req.dir.empty()) throw InputError("(export folder)", "no folder given");
  if (req.path.empty()) throw InputError(req.dir, "nothing to export: the path is empty");
  if (req.models.empty()) throw InputError(req.dir, "nothing to export: no model is shown");
  for (const auto& m : req.models) {
    const fs::path folder = fs::path(req.dir) / m.id;
    if (fs::exists(folder) && !is_field_export(folder))
      throw InputError(folder.string(), "exists and is not a shearbench field export; choose another folder");
  }
}

int export_fields(const FieldExportRequest& req, const Progress& progress) {
  check_export_target(req);
  const double total_steps = static_cast<double>(req.models.size() * req.path.size());
  std::vector<PredictionExport> exports;
  exports.reserve(req.models.size());
  for (std::size_t i = 0; i < req.models.size(); ++i) {
    const FieldExportModel& m = req.models[i];
    progress.check("field export");
    auto model = make_spec_model(m.id, req.sensor, req.indenter);
    model->set_params(m.params);
    const double done_before = static_cast<double>(i * req.path.size());
    PredictionExport e = describe(req, m);
    e.disp_px = predict_along(*model, req.path, req.dt_s, progress.cancel, [&](std::size_t steps) {
      progress(m.id, (done_before + static_cast<double>(steps)) / total_steps);
    });
    // predict_along returns early (empty) when the flag is set.
    progress.check("field export");
    exports.push_back(std::move(e));
  }
  progress("writing", 1.0);
  for (std::size_t i = 0; i < exports.size(); ++i)
    write_prediction_dataset((fs::path(req.dir) / req.models[i].id).string(), exports[i]);
  return static_cast<int>(exports.size());
}

// ------------------------------------------------------------------------------------ FieldExportJob

void FieldExportJob::start(FieldExportRequest request) {
  FieldExportStatus running;
  running.phase = FieldExportStatus::Phase::kRunning;
  running.dir = request.dir;
  job_.start(std::move(running),
             [req = std::move(request)](const std::atomic<bool>& cancel, Job& job) { run(req, cancel, job); });
}

void FieldExportJob::run(const FieldExportRequest& req, const std::atomic<bool>& cancel, Job& job) {
  Progress progress;
  progress.cancel = &cancel;
  progress.report = [&job](const std::string& stage, double fraction) {
    job.update([&](FieldExportStatus& s) {
      s.stage = stage;
      s.fraction = fraction;
    });
  };
  FieldExportStatus end;
  end.dir = req.dir;
  try {
    end.written = export_fields(req, progress);
    end.phase = FieldExportStatus::Phase::kDone;
    end.fraction = 1;
  } catch (const Cancelled&) {
    end.phase = FieldExportStatus::Phase::kCancelled;
  } catch (const std::exception& e) {
    end.phase = FieldExportStatus::Phase::kFailed;
    end.error = e.what();
  }
  job.update([&](FieldExportStatus& s) {
    end.stage = s.stage;
    if (end.phase != FieldExportStatus::Phase::kDone) end.fraction = s.fraction;
    s = std::move(end);
  });
}

}  // namespace sb
