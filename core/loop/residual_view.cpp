#include "core/loop/residual_view.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "core/base/error.hpp"
#include "core/base/numbers.hpp"
#include "core/calibration/prediction_export.hpp"
#include "core/data/json_read.hpp"
#include "core/effects/effects.hpp"
#include "core/effects/model_spec.hpp"
#include "core/loop/residual_structure.hpp"

namespace sb {

namespace {

// A metric the report wrote as null (nothing to score) reads as NaN.
double number_or_nan(const nlohmann::json& obj, const char* key, const std::string& file, const std::string& ptr) {
  const nlohmann::json& v = jsonin::member(obj, key, file, ptr);
  return v.is_null() ? kNaN : jsonin::finite_number(v, file, jsonin::child(ptr, key));
}

std::vector<std::string> effect_list(const nlohmann::json& j, const std::string& file, const std::string& ptr) {
  if (!j.is_array()) jsonin::fail(file, ptr, "expected an array of effect ids");
  std::vector<std::string> ids;
  const auto& known = effect_ids();
  for (std::size_t i = 0; i < j.size(); ++i) {
    ids.push_back(jsonin::string(j[i], file, jsonin::child(ptr, i)));
    if (std::find(known.begin(), known.end(), ids.back()) == known.end())
      jsonin::fail(file, jsonin::child(ptr, i), "unknown effect '" + ids.back() + "'");
  }
  return ids;
}

// `selected`: effect ids (older reports) or {"effect", "fingerprint_found", "evidence"} objects.
std::vector<SelectedEffectView> selected_list(const nlohmann::json& j, const std::string& file) {
  if (!j.is_array()) jsonin::fail(file, "/selected", "expected an array of effects");
  std::vector<SelectedEffectView> out;
  nlohmann::json ids = nlohmann::json::array();
  for (std::size_t i = 0; i < j.size(); ++i) {
    const std::string ptr = jsonin::child("/selected", i);
    SelectedEffectView v;
    if (j[i].is_object()) {
      ids.push_back(jsonin::member(j[i], "effect", file, ptr));
      const nlohmann::json& found = jsonin::member(j[i], "fingerprint_found", file, ptr);
      if (!found.is_boolean()) jsonin::fail(file, ptr + "/fingerprint_found", "expected true or false");
      v.recorded = true;
      v.found = found.get<bool>();
      v.evidence = jsonin::string(jsonin::member(j[i], "evidence", file, ptr), file, ptr + "/evidence");
    } else {
      ids.push_back(j[i]);
    }
    out.push_back(v);
  }
  const auto names = effect_list(ids, file, "/selected");
  for (std::size_t i = 0; i < names.size(); ++i) out[i].effect = names[i];
  return out;
}

std::vector<AtBoundView> at_bound_list(const nlohmann::json& j, const std::string& file) {
  if (!j.is_array()) jsonin::fail(file, "/answer_at_bound", "expected an array");
  std::vector<AtBoundView> out;
  for (std::size_t i = 0; i < j.size(); ++i) {
    const std::string ptr = jsonin::child("/answer_at_bound", i);
    AtBoundView v;
    v.param = jsonin::string(jsonin::member(j[i], "param", file, ptr), file, ptr + "/param");
    v.bound = jsonin::string(jsonin::member(j[i], "bound", file, ptr), file, ptr + "/bound");
    v.value = number_or_nan(j[i], "value", file, ptr);
    const nlohmann::json& d = jsonin::member(j[i], "is_default", file, ptr);
    v.is_default = d.is_boolean() && d.get<bool>();
    out.push_back(v);
  }
  return out;
}

// The candidate's verdict in two words, from the fields residual_to_json writes.
// rules_recorded: the report lists model-form symptoms (written since the selection records its vetoes and
// fingerprints); an older one has only the reason's text, and the verdict does not guess from it.
std::string candidate_verdict(const nlohmann::json& c, const ResidualCandidateView& v, bool rules_recorded) {
  const auto* symptom = jsonin::find(c, "model_form_symptom");
  const auto* veto = jsonin::find(c, "veto");
  const std::string veto_text = veto && veto->is_string() ? veto->get<std::string>() : "";
  const auto* fingerprint = jsonin::find(c, "fingerprint");
  const auto* found = fingerprint && fingerprint->is_object() ? jsonin::find(*fingerprint, "found") : nullptr;
  if (v.accepted) return "selected";
  if (!std::isfinite(v.improvement_pct)) return "not scored";
  if (!rules_recorded) return "not selected";
  // As the selection words its reason: a fingerprint not found first, then the veto.
  if (found && found->is_boolean() && !found->get<bool>()) return "no evidence";
  if (symptom && symptom->is_boolean() && symptom->get<bool>()) return "at a bound";
  if (veto_text.rfind("screened", 0) == 0) return "screened";
  if (!veto_text.empty()) return "vetoed";
  return "within noise";
}

ResidualCandidateView read_candidate(const nlohmann::json& c, const std::string& file, const std::string& ptr,
                                     bool rules_recorded) {
  jsonin::require_object(c, file, ptr);
  ResidualCandidateView v;
  v.effect = jsonin::string(jsonin::member(c, "effect", file, ptr), file, jsonin::child(ptr, "effect"));
  v.validation_rmse_px = number_or_nan(c, "validation_rmse_px", file, ptr);
  v.improvement_pct = number_or_nan(c, "improvement_pct", file, ptr);
  const std::string ci_ptr = jsonin::child(ptr, "ci95_pct");
  const nlohmann::json& ci = jsonin::member(c, "ci95_pct", file, ptr);
  if (!ci.is_array() || ci.size() != 2) jsonin::fail(file, ci_ptr, "expected [low, high]");
  v.ci95_low_pct = ci[0].is_null() ? kNaN : jsonin::finite_number(ci[0], file, jsonin::child(ci_ptr, std::size_t{0}));
  v.ci95_high_pct = ci[1].is_null() ? kNaN : jsonin::finite_number(ci[1], file, jsonin::child(ci_ptr, std::size_t{1}));
  if (const auto* a = jsonin::find(c, "accepted"))
    v.accepted = jsonin::boolean(*a, file, jsonin::child(ptr, "accepted"));
  if (const auto* r = jsonin::find(c, "reason")) v.reason = jsonin::string(*r, file, jsonin::child(ptr, "reason"));
  v.verdict = candidate_verdict(c, v, rules_recorded);
  return v;
}

}  // namespace

namespace {

// The contact-frame tables of "residual_before" (reports written before they existed have none).
// The base model's input-response rows; none when the report has no analysis (older, or a split without frames).
void read_input_response(const nlohmann::json& j, const std::string& path, ResidualSummary* s) {
  const auto* a = jsonin::find(j, "input_response_before");
  if (a == nullptr || a->is_null()) return;
  const nlohmann::json& rows = jsonin::member(*a, "responses", path, "/input_response_before");
  if (!rows.is_array()) jsonin::fail(path, "/input_response_before/responses", "expected an array");
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const std::string ptr = jsonin::child("/input_response_before/responses", i);
    const auto num = [&](const char* key) {
      return jsonin::finite_number(jsonin::member(rows[i], key, path, ptr), path, ptr + "/" + key);
    };
    s->input_response.push_back({jsonin::string(jsonin::member(rows[i], "change", path, ptr), path, ptr + "/change"),
                                 num("measured_rms_px"), num("model_rms_px"), num("gain"), num("after_gain_rms_px")});
  }
  s->inputs_only_rmse_px =
      jsonin::finite_number(jsonin::member(*a, "inputs_only_rmse_px", path, "/input_response_before"), path,
                            "/input_response_before/inputs_only_rmse_px");
}

std::vector<ContactFrameTableView> read_contact_frame(const nlohmann::json& j, const std::string& path) {
  std::vector<ContactFrameTableView> out;
  const auto* before = jsonin::find(j, "residual_before");
  const auto* cov = before ? jsonin::find(*before, "covariates") : nullptr;
  if (cov == nullptr || !cov->is_array()) return out;
  for (std::size_t i = 0; i < cov->size(); ++i) {
    const std::string ptr = jsonin::child("/residual_before/covariates", i);
    const nlohmann::json& t = (*cov)[i];
    const nlohmann::json& bins = jsonin::member(t, "bins", path, ptr);
    if (!bins.is_array() || bins.empty() || !bins[0].contains("mean_radial_px")) continue;
    ContactFrameTableView v;
    v.name = jsonin::string(jsonin::member(t, "covariate", path, ptr), path, ptr + "/covariate");
    v.unit = jsonin::string(jsonin::member(t, "unit", path, ptr), path, ptr + "/unit");
    for (std::size_t b = 0; b < bins.size(); ++b) {
      const std::string bp = jsonin::child(ptr + "/bins", b);
      v.bins.push_back(jsonin::string(jsonin::member(bins[b], "bin", path, bp), path, bp + "/bin"));
      v.count.push_back(
          static_cast<long>(jsonin::finite_number(jsonin::member(bins[b], "count", path, bp), path, bp + "/count")));
      v.rms_px.push_back(number_or_nan(bins[b], "rms_px", path, bp));
      v.mean_radial_px.push_back(number_or_nan(bins[b], "mean_radial_px", path, bp));
      v.mean_along_px.push_back(number_or_nan(bins[b], "mean_along_travel_px", path, bp));
    }
    out.push_back(std::move(v));
  }
  return out;
}

// The base model's mean residual per bin of depth, travel and tilt direction, summarised per bin (the report's
// maps are PNGs beside it). Empty bins are left out.
std::vector<BinnedMeanView> read_binned_means(const nlohmann::json& j, const std::string& path) {
  std::vector<BinnedMeanView> out;
  const auto* before = jsonin::find(j, "residual_before");
  const auto* binned = before ? jsonin::find(*before, "binned_mean_fields") : nullptr;
  if (binned == nullptr) return out;
  if (!binned->is_array()) jsonin::fail(path, "/residual_before/binned_mean_fields", "expected an array");
  for (std::size_t i = 0; i < binned->size(); ++i) {
    const std::string ptr = jsonin::child("/residual_before/binned_mean_fields", i);
    const std::string name =
        jsonin::string(jsonin::member((*binned)[i], "covariate", path, ptr), path, ptr + "/covariate");
    const nlohmann::json& bins = jsonin::member((*binned)[i], "bins", path, ptr);
    if (!bins.is_array()) jsonin::fail(path, ptr + "/bins", "expected an array");
    for (std::size_t b = 0; b < bins.size(); ++b) {
      const std::string bp = jsonin::child(ptr + "/bins", b);
      BinnedMeanView v{name, jsonin::string(jsonin::member(bins[b], "bin", path, bp), path, bp + "/bin")};
      v.frames =
          static_cast<long>(jsonin::finite_number(jsonin::member(bins[b], "frames", path, bp), path, bp + "/frames"));
      const nlohmann::json& field = jsonin::member(bins[b], "mean_px", path, bp);
      if (!field.is_array()) jsonin::fail(path, bp + "/mean_px", "expected an array of [x, y]");
      std::vector<Vec2> mean;
      mean.reserve(field.size());
      for (std::size_t m = 0; m < field.size(); ++m) {
        const std::string mp = jsonin::child(bp + "/mean_px", m);
        if (!field[m].is_array() || field[m].size() != 2) jsonin::fail(path, mp, "expected [x, y]");
        mean.emplace_back(jsonin::finite_number(field[m][0], path, mp + "/0"),
                          jsonin::finite_number(field[m][1], path, mp + "/1"));
      }
      if (v.frames == 0 || mean.empty()) continue;
      const FieldSummary f = summarise_field(mean);
      v.rms_px = f.rms_px;
      v.shift_px = f.shift_px;
      out.push_back(std::move(v));
    }
  }
  return out;
}

}  // namespace

ResidualSummary load_residual_summary(const std::string& path) {
  const nlohmann::json j = jsonin::load_file(path);
  jsonin::require_object(j, path, "");
  ResidualSummary s;
  s.file = path;
  if (const auto* d = jsonin::find(j, "dataset")) s.dataset = jsonin::string(*d, path, "/dataset");
  s.model_id = jsonin::string(jsonin::member(j, "model", path, ""), path, "/model");
  try {
    (void)default_params(s.model_id);
  } catch (const std::exception& e) {
    jsonin::fail(path, "/model", e.what());
  }
  const nlohmann::json& before = jsonin::member(j, "before", path, "");
  jsonin::require_object(before, path, "/before");
  s.before_rmse_px = number_or_nan(before, "validation_rmse_px", path, "/before");
  s.before_params = jsonin::member(before, "params", path, "/before");
  jsonin::require_object(s.before_params, path, "/before/params");
  const nlohmann::json& after = jsonin::member(j, "after", path, "");
  jsonin::require_object(after, path, "/after");
  s.after_rmse_px = number_or_nan(after, "validation_rmse_px", path, "/after");
  s.after_params = jsonin::member(after, "params", path, "/after");
  jsonin::require_object(s.after_params, path, "/after/params");
  s.selected_evidence = selected_list(jsonin::member(j, "selected", path, ""), path);
  for (const auto& v : s.selected_evidence) s.selected.push_back(v.effect);
  if (const auto* b = jsonin::find(j, "answer_at_bound")) s.answer_at_bound = at_bound_list(*b, path);
  if (const auto* form = jsonin::find(j, "model_form_selected"))
    s.model_form = jsonin::string(*form, path, "/model_form_selected");
  s.after_model = ModelSpec{s.model_id, s.selected}.id();
  if (const auto* m = jsonin::find(j, "after_model")) s.after_model = jsonin::string(*m, path, "/after_model");
  try {
    if (parse_model_spec(s.after_model).effects != s.selected)
      jsonin::fail(path, "/after_model", "its effects differ from /selected");
  } catch (const std::invalid_argument& e) {
    jsonin::fail(path, "/after_model", e.what());
  }
  // The corrected model is the one "after" was fitted with: it must be the selection.
  const auto after_effects = effect_list(jsonin::member(after, "effects", path, "/after"), path, "/after/effects");
  if (after_effects != s.selected) jsonin::fail(path, "/after/effects", "differs from /selected");

  s.answer_labelled = s.after_model;
  if (const auto* l = jsonin::find(j, "answer_labelled"))
    s.answer_labelled = jsonin::string(*l, path, "/answer_labelled");

  const nlohmann::json& cands = jsonin::member(j, "candidates", path, "");
  if (!cands.is_array()) jsonin::fail(path, "/candidates", "expected an array");
  const bool rules_recorded = jsonin::find(j, "model_form_symptoms") != nullptr;
  for (std::size_t i = 0; i < cands.size(); ++i)
    s.candidates.push_back(read_candidate(cands[i], path, jsonin::child("/candidates", i), rules_recorded));
  // A selected effect's verdict says whether its evidence was found (reports that record it).
  for (auto& c : s.candidates)
    for (const auto& v : s.selected_evidence)
      if (v.recorded && c.effect == v.effect && c.verdict == "selected")
        c.verdict = v.found ? "found" : "unshown cause";
  // Ranked: largest improvement first; an unscored (NaN) candidate last.
  std::stable_sort(s.candidates.begin(), s.candidates.end(), [](const auto& a, const auto& b) {
    const double ia = std::isfinite(a.improvement_pct) ? a.improvement_pct : -1e300;
    const double ib = std::isfinite(b.improvement_pct) ? b.improvement_pct : -1e300;
    return ia > ib;
  });
  // The parameter table must fit the corrected model (names and ranges): check it here, where the
  // error can still name the file.
  try {
    ParamSet p = model_spec_params(s.after_model);
    p.update_from_json(s.after_params, path + ": /after/params");
    (void)fitted_base_params(s);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    jsonin::fail(path, "/after/params", e.what());
  }
  s.contact_frame = read_contact_frame(j, path);
  s.binned_means = read_binned_means(j, path);
  read_input_response(j, path, &s);
  return s;
}

ParamSet fitted_base_params(const ResidualSummary& summary) {
  ParamSet p = default_params(summary.model_id);
  p.update_from_json(summary.before_params, summary.file + ": /before/params");
  return p;
}

std::unique_ptr<ShearModel> make_corrected_model(const ResidualSummary& summary, std::shared_ptr<const Sensor> sensor,
                                                 std::shared_ptr<const Indenter> indenter) {
  auto model = make_spec_model(summary.after_model, std::move(sensor), std::move(indenter));
  ParamSet p = model->params();
  p.update_from_json(summary.after_params, summary.file + ": /after/params");
  model->set_params(p);
  return model;
}

std::vector<Vec2> residual_field(const std::vector<Vec2>& measured, const std::vector<Vec2>& predicted) {
  std::vector<Vec2> r(measured.size(), Vec2(kNaN, kNaN));
  for (std::size_t i = 0; i < measured.size() && i < predicted.size(); ++i) r[i] = measured[i] - predicted[i];
  return r;  // NaN - x stays NaN: a lost marker stays lost
}

// ------------------------------------------------------------------------------ FieldSeriesJob

FieldSeriesJob::~FieldSeriesJob() { clear(); }

void FieldSeriesJob::clear() {
  cancel_ = true;
  if (future_.valid()) future_.wait();
  future_ = {};
  result_.clear();
}

void FieldSeriesJob::start(std::unique_ptr<ShearModel> model, std::vector<Pose> path, double dt_s) {
  clear();
  cancel_ = false;
  // The model moves into the task: the worker owns everything it touches.
  future_ =
      std::async(std::launch::async, [this, m = std::shared_ptr<ShearModel>(std::move(model)), path = std::move(path),
                                      dt_s] { return predict_along(*m, path, dt_s, &cancel_); });
}

bool FieldSeriesJob::running() const {
  return future_.valid() && future_.wait_for(std::chrono::seconds(0)) != std::future_status::ready;
}

void FieldSeriesJob::wait() const {
  if (future_.valid()) future_.wait();
}

const std::vector<std::vector<Vec2>>& FieldSeriesJob::result() {
  if (future_.valid() && !running()) result_ = future_.get();  // an exception in the worker propagates
  return result_;
}

}  // namespace sb
