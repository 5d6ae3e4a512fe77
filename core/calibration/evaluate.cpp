#include "core/calibration/evaluate.hpp"
#include "core/base/reproducible.hpp"

#include <tbb/parallel_for.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <mutex>

#include "core/base/format.hpp"
#include "core/data/json_read.hpp"

namespace sb {

bool split_selected(const std::string& split_filter, const std::string& sample_split, const std::string& where) {
  if (split_filter == "all") return true;
  if (!is_tsd_split(split_filter))
    throw InputError(where, "unknown split '" + split_filter + "' (expected calibration, validation or all)");
  return split_filter == sample_split;
}

void run_sample(ShearModel& model, const SampleData& data, double dt_s, MetricsAccumulator* acc,
                std::vector<ScoredFrame>* fields) {
  model.reset();
  FieldOutput out;
  for (std::size_t k = 0; k < data.frames(); ++k) {
    const auto& meas = data.markers_px[k];
    if (nothing_tracked(meas)) {
      model.step(data.X_EI(k), dt_s, nullptr);  // nothing tracked in this frame: no field to score
      continue;
    }
    model.step(data.X_EI(k), dt_s, &out);
    const long long before = acc->frames_counted();
    acc->add_frame(out.disp_px, meas);
    if (fields && acc->frames_counted() > before) fields->push_back({static_cast<int>(k), out.disp_px, meas});
  }
}

EvaluationResult evaluate_dataset(const Dataset& ds, const ModelFactory& factory, const std::string& split_filter,
                                  const std::string& model_id, Warnings* warnings, bool keep_fields) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<const TsdSampleInfo*> selected;
  for (const auto& s : ds.samples)
    if (split_selected(split_filter, s.split, "--split")) selected.push_back(&s);

  std::vector<SampleEvaluation> per_sample(selected.size());
  std::vector<Warnings> sample_warnings(selected.size());
  tbb::parallel_for(std::size_t{0}, selected.size(), [&](std::size_t i) {
    const TsdSampleInfo& info = *selected[i];
    const SampleData data = read_sample(ds, info.id, &sample_warnings[i]);
    std::unique_ptr<ShearModel> model = factory(info);
    per_sample[i].sample_id = info.id;
    per_sample[i].motion = info.motion;
    run_sample(*model, data, info.dt_s, &per_sample[i].metrics, keep_fields ? &per_sample[i].fields : nullptr);
  });

  EvaluationResult result;
  result.model_id = model_id;
  for (const auto& s : per_sample) result.metrics.add(s.motion, s.metrics);
  result.samples = std::move(per_sample);
  if (warnings)
    for (auto& w : sample_warnings)
      for (auto& m : w.messages) warnings->add(std::move(m));
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

nlohmann::json params_for_model(const nlohmann::json& params_file, const std::string& model_id, bool flat_allowed,
                                const std::string& where) {
  if (params_file.is_null()) return nlohmann::json::object();
  jsonin::require_object(params_file, where, "");
  bool all_objects = true, all_numbers = true;
  for (const auto& [k, v] : params_file.items()) {
    all_objects = all_objects && v.is_object();
    all_numbers = all_numbers && v.is_number();
  }
  if (params_file.empty()) return nlohmann::json::object();
  if (all_objects) {
    const auto* table = jsonin::find(params_file, model_id.c_str());
    return table ? *table : nlohmann::json::object();
  }
  if (all_numbers) {
    if (!flat_allowed)
      jsonin::fail(where, "",
                   "a flat parameter table is for one model; key it by model id ({\"" + model_id +
                       "\": {...}}) when running several");
    return params_file;
  }
  jsonin::fail(where, "", "expected {model id: {name: number}} or a flat {name: number} table");
}

namespace {

// The motion columns present in the results, in tsd/1 order (free only when a dataset has it).
std::vector<std::string> motion_columns(const std::vector<EvaluationResult>& results) {
  std::vector<std::string> cols;
  for (const auto& m : tsd_motions()) {
    bool present = m != "free";
    for (const auto& r : results) present = present || r.metrics.per_motion.count(m);
    if (present) cols.push_back(m);
  }
  return cols;
}

nlohmann::ordered_json result_json(const MetricsAccumulator& acc) {
  const MetricsResult r = acc.result();
  nlohmann::ordered_json j;
  j["rmse_px"] = r.n > 0 ? nlohmann::ordered_json(r.rmse_px) : nlohmann::ordered_json(nullptr);
  j["cs"] = r.n_cs > 0 ? nlohmann::ordered_json(r.cs) : nlohmann::ordered_json(nullptr);
  j["n"] = r.n;
  j["n_cs"] = r.n_cs;
  return j;
}

}  // namespace

nlohmann::ordered_json evaluation_to_json(const std::vector<EvaluationResult>& results, const Dataset& ds,
                                          const std::string& split_filter) {
  nlohmann::ordered_json j;
  j["dataset"] = ds.name;
  j["dataset_dir"] = ds.dir;
  j["split"] = split_filter;
  j["metric"] = "RMSE px and cosine similarity over marker-frames of frames with a measured marker moving >= 0.5 px";
  nlohmann::ordered_json models = nlohmann::ordered_json::object();
  for (const auto& r : results) {
    nlohmann::ordered_json m;
    for (const auto& motion : tsd_motions()) {
      const auto it = r.metrics.per_motion.find(motion);
      if (it != r.metrics.per_motion.end()) m[motion] = result_json(it->second);
    }
    m["overall"] = result_json(r.metrics.overall);
    if (timings_in_outputs()) m["seconds"] = r.seconds;
    nlohmann::ordered_json samples = nlohmann::ordered_json::object();
    for (const auto& s : r.samples) samples[s.sample_id] = result_json(s.metrics);
    m["samples"] = samples;
    models[r.model_id] = m;
  }
  j["models"] = models;
  return j;
}

std::string evaluation_to_markdown(const std::vector<EvaluationResult>& results, const std::string& title) {
  const auto cols = motion_columns(results);
  std::string s = "### " + title + "\n\n| Model |";
  std::string rule = "|---|";
  for (const auto& c : cols) {
    std::string name = c;
    name[0] = static_cast<char>(std::toupper(name[0]));
    s += " " + name + " RMSE (px) | " + name + " CS |";
    rule += "---:|---:|";
  }
  s += " Overall RMSE (px) | Overall CS | n |\n" + rule + "---:|---:|---:|\n";
  for (const auto& r : results) {
    s += "| " + r.model_id + " |";
    for (const auto& c : cols) {
      const auto it = r.metrics.per_motion.find(c);
      const MetricsResult m = it == r.metrics.per_motion.end() ? MetricsAccumulator{}.result() : it->second.result();
      s += " " + format_number(m.rmse_px, "%.3f", "–") + " | " + format_number(m.cs, "%.3f", "–") + " |";
    }
    const MetricsResult o = r.metrics.overall.result();
    s += " " + format_number(o.rmse_px, "%.3f", "–") + " | " + format_number(o.cs, "%.3f", "–") + " | " +
         std::to_string(o.n) + " |\n";
  }
  return s;
}

std::string scored_fields_csv(const EvaluationResult& result) {
  std::string out = "sample,motion,frame,marker,meas_du_px,meas_dv_px,pred_du_px,pred_dv_px\n";
  for (const SampleEvaluation& s : result.samples)
    for (const ScoredFrame& f : s.fields)
      for (std::size_t j = 0; j < f.meas_px.size(); ++j) {
        const Vec2& m = f.meas_px[j];
        const Vec2& p = f.pred_px[j];
        out += s.sample_id + "," + s.motion + "," + std::to_string(f.frame) + "," + std::to_string(j) + "," +
               format_number(m.x(), "%.4f", "nan") + "," + format_number(m.y(), "%.4f", "nan") + "," +
               format_number(p.x(), "%.4f", "nan") + "," + format_number(p.y(), "%.4f", "nan") + "\n";
      }
  return out;
}

}  // namespace sb
