#include "core/calibration/report.hpp"
#include "core/base/reproducible.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "core/base/format.hpp"
#include "core/calibration/fit_data.hpp"

namespace sb {

namespace {

// The HydroShear paper's calibration table (real GelSight Mini, 35 mm sphere), for scale only.
struct PaperRow {
  const char* model;
  double rmse[4], cs[4];
};
constexpr PaperRow kPaper[] = {
    {"HydroShear", {1.000, 1.719, 2.021, 1.576}, {0.976, 0.951, 0.974, 0.904}},
    {"FOTS", {1.333, 2.146, 3.596, 2.841}, {0.976, 0.930, 0.683, 0.561}},
    {"TacSL", {2.187, 4.262, 4.022, 3.861}, {0.323, 0.126, 0.157, 0.137}},
};

std::string paper_table() {
  std::string s =
      "| Model | Dilation RMSE (px) | Dilation CS | Shear RMSE (px) | Shear CS | Twist RMSE (px) | Twist CS | "
      "Roll RMSE (px) | Roll CS |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& r : kPaper) {
    s += std::string("| ") + r.model + " |";
    for (int i = 0; i < 4; ++i) s += " " + format_number(r.rmse[i]) + " | " + format_number(r.cs[i]) + " |";
    s += "\n";
  }
  return s;
}

MetricsResult motion_result(const EvaluationResult& e, const std::string& motion) {
  const auto it = e.metrics.per_motion.find(motion);
  return it == e.metrics.per_motion.end() ? MetricsAccumulator{}.result() : it->second.result();
}

std::vector<std::string> motions_of(const DatasetFidelity& r) {
  std::vector<std::string> out;
  for (const auto& m : tsd_motions())
    for (const auto& e : r.fitted)
      if (e.metrics.per_motion.count(m) && std::find(out.begin(), out.end(), m) == out.end()) out.push_back(m);
  return out;
}

std::string params_table(const DatasetFidelity& r) {
  std::string s =
      "| Model | Fitted parameters (changed from default) | Stages: RMSE before -> after (px), iterations, s |\n"
      "|---|---|---|\n";
  for (const auto& f : r.fits) {
    const ParamSet def = default_params(f.model_id);
    std::string ps, st;
    for (std::size_t i = 0; i < f.params.size(); ++i)
      if (f.params[i] != def[i])
        ps += (ps.empty() ? "" : ", ") + f.params.specs()[i].name + " = " + format_number(f.params[i], "%.4g");
    for (const auto& g : f.stages) {
      st += (st.empty() ? "" : "; ") + g.name + ": ";
      st += g.skipped ? "skipped"
                      : format_number(g.rmse_before_px) + " -> " + format_number(g.rmse_after_px) + ", " +
                            std::to_string(g.iterations) + " it" +
                            (timings_in_outputs() ? ", " + format_number(g.time_s, "%.1f") + " s" : std::string());
      if (!g.note.empty()) st += " (" + g.note + ")";
    }
    s += "| " + f.model_id + " | " + (ps.empty() ? "(defaults)" : ps) + " | " + st + " |\n";
  }
  return s;
}

}  // namespace

std::vector<DatasetFidelity> run_fidelity(const FidelityOptions& o) {
  std::vector<DatasetFidelity> out;
  const std::vector<std::string> ids = o.models.empty() ? model_ids() : o.models;
  for (const auto& dir_in : o.dataset_dirs) {
    const auto t0 = std::chrono::steady_clock::now();
    Dataset ds = read_dataset(std::filesystem::absolute(dir_in).string());
    if (!o.calibration_ids.empty())
      assign_calibration_split(ds, o.calibration_ids, "calibration samples", o.validation_ids);
    DatasetFidelity r;
    r.dataset = ds.name;
    r.dir = dir_in;
    Warnings w;
    const FitData data = load_calibration_data(ds, o.data_root, &w);
    for (const auto& id : ids) {
      const auto t1 = std::chrono::steady_clock::now();
      r.fits.push_back(fit_model(id, data.sensor, data.samples, default_params(id), o.fit));
      const double t_fit = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
      r.fitted.push_back(
          evaluate_dataset(ds, dataset_model_factory(ds, id, r.fits.back().params.to_json(), o.data_root, "fit", &w),
                           "validation", id, &w));
      r.defaults.push_back(
          evaluate_dataset(ds, dataset_model_factory(ds, id, nlohmann::json::object(), o.data_root, "defaults", &w),
                           "validation", id, &w));
      if (o.log) {
        const MetricsResult m = r.fitted.back().metrics.overall.result();
        o.log(ds.name + " " + id + ": fit " + format_number(t_fit, "%.1f") + " s, validation RMSE " +
              format_number(m.rmse_px) + " px, CS " + format_number(m.cs));
      }
      if (o.fit.cancel && o.fit.cancel->load()) break;
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    out.push_back(std::move(r));
    if (o.fit.cancel && o.fit.cancel->load()) break;
  }
  return out;
}

std::string fidelity_reading(const DatasetFidelity& r) {
  std::string s;
  const EvaluationResult* hs = nullptr;
  for (const auto& e : r.fitted)
    if (e.model_id == "hydroshear") hs = &e;
  for (const auto& m : motions_of(r)) {
    const EvaluationResult *best_rmse = nullptr, *best_cs = nullptr;
    for (const auto& e : r.fitted) {
      const MetricsResult x = motion_result(e, m);
      if (!best_rmse || x.rmse_px < motion_result(*best_rmse, m).rmse_px) best_rmse = &e;
      if (!best_cs || x.cs > motion_result(*best_cs, m).cs) best_cs = &e;
    }
    s += "- **" + m + "**: lowest RMSE " + best_rmse->model_id + " (" +
         format_number(motion_result(*best_rmse, m).rmse_px) + " px), highest CS " + best_cs->model_id + " (" +
         format_number(motion_result(*best_cs, m).cs) + ")";
    if (hs && best_rmse != hs) {
      const double a = motion_result(*hs, m).rmse_px, b = motion_result(*best_rmse, m).rmse_px;
      s += "; HydroShear is " + format_number(a) + " px, " + format_number(100 * (a - b) / b, "%.0f") +
           " % above the best";
    } else if (hs) {
      s += "; HydroShear is the lowest";
    }
    s += ".\n";
  }
  return s;
}

std::string fidelity_markdown(const std::vector<DatasetFidelity>& results, const FidelityOptions& o,
                              const std::string& analysis) {
  std::string s =
      "# Fidelity of the shear models on the digital-twin datasets\n\n"
      "Generated by `shearbench report` (app/cmd_report.cpp, core/calibration/report.cpp). Every model is fitted on "
      "the "
      "dataset's **calibration** split (`core/calibration/fit.hpp`: staged least squares, a bounded "
      "Levenberg-Marquardt, "
      "log-space parameters inside their ranges";
  s += o.fit.joint ? ", stages followed by a joint refinement on every calibration motion" : "";
  s += ", robust loss: " + to_string(o.fit.robust) +
       ") and scored on its **validation** split (`core/calibration/evaluate.hpp`, metric of "
       "`core/calibration/metrics.hpp`: "
       "frames where a measured marker moves >= 0.5 px, every non-NaN marker in them; RMSE in px, CS = mean "
       "cosine over markers moving >= 0.5 px). All frames are used (no subsampling). The datasets are "
       "synthetic (a linear-elastic FE gel with Coulomb stick-slip contact, not real GelSight data).\n\n";
  s += "## The paper's table, for scale\n\nHydroShear paper, real GelSight Mini, 35 mm sphere. Different data: "
       "compare orderings, not values.\n\n" +
       paper_table() + "\n";
  for (const auto& r : results) {
    s += "## " + r.dataset + "\n\n";
    std::vector<EvaluationResult> rows = r.fitted;
    s += evaluation_to_markdown(rows, r.dataset + " (validation, fitted on calibration)") + "\n";
    s += "Reading (generated from the numbers above):\n\n" + fidelity_reading(r) + "\n";
    s += evaluation_to_markdown(r.defaults, r.dataset + " (validation, default parameters, for reference)") + "\n";
    s += "Fitted parameters:\n\n" + params_table(r) + "\n";
    if (timings_in_outputs())
      s += "Wall time for this dataset (fits and evaluations, 2 cores): " + format_number(r.seconds, "%.0f") +
           " s.\n\n";
  }
  if (!analysis.empty()) s += analysis + "\n";
  return s;
}

}  // namespace sb
