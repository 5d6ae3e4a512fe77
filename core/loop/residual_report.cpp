// The residual loop's report as JSON (residual_report.hpp).
#include "core/loop/residual_report.hpp"

#include <algorithm>
#include <cmath>

#include "core/base/reproducible.hpp"
#include "core/effects/effects.hpp"
#include "core/loop/residual_report_format.hpp"

namespace sb {

namespace {

// JSON has no NaN: empty metrics become null.
nlohmann::ordered_json json_num(double v) { return std::isfinite(v) ? nlohmann::ordered_json(v) : nullptr; }

// A candidate's score against the model it extends (effects and model forms alike).
void add_score_json(const CandidateScore& c, nlohmann::ordered_json* j) {
  (*j)["validation_rmse_px"] = json_num(c.rmse_px);
  (*j)["improvement_pct"] = json_num(c.improvement_pct);
  (*j)["ci95_pct"] = {json_num(c.improvement_ci_pct.low), json_num(c.improvement_ci_pct.high)};
  (*j)["delta_bic"] = json_num(c.delta_bic);
  (*j)["accepted"] = c.accepted;
  (*j)["reason"] = c.reason;
}

nlohmann::ordered_json metrics_json(const EffectFit& f) {
  nlohmann::ordered_json by = nlohmann::ordered_json::object();
  for (const auto& [motion, acc] : f.validation.per_motion) {
    const MetricsResult m = acc.result();
    by[motion] = {{"rmse_px", json_num(m.rmse_px)}, {"cs", json_num(m.cs)}, {"n", m.n}};
  }
  const MetricsResult all = f.validation.overall.result();
  nlohmann::ordered_json j;
  j["effects"] = f.effects;
  j["validation_rmse_px"] = json_num(all.rmse_px);
  j["validation_cs"] = json_num(all.cs);
  j["by_motion"] = by;
  j["calibration_rmse_px"] = json_num(std::sqrt(2 * f.fit.calibration_sse_px2 / f.fit.calibration_count));
  j["free_params"] = f.fit.free_params;
  if (f.fit.held_count > 0)
    j["held_drift"] = {{"marker_frames", f.fit.held_count},
                       {"measured_rms_px", json_num(std::sqrt(f.fit.held_signal_px2 / f.fit.held_count))},
                       {"error_rms_px", json_num(std::sqrt(f.fit.held_sse_px2 / f.fit.held_count))}};
  if (!f.fit.veto.empty()) j["veto"] = f.fit.veto;
  j["params"] = f.fit.params.to_json();
  if (timings_in_outputs()) j["fit_time_s"] = f.time_s;
  return j;
}

nlohmann::ordered_json response_json(const std::optional<InputResponseAnalysis>& a) {
  if (!a) return nullptr;
  nlohmann::ordered_json j;
  j["reference"] = {{"depth_m", a->reference.depth_m},
                    {"tilt", {a->reference.tilt.x(), a->reference.tilt.y()}},
                    {"travel_m", {a->reference.travel_m.x(), a->reference.travel_m.y()}},
                    {"twist_rad", a->reference.twist_rad}};
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (const auto& x : a->responses)
    rows.push_back({{"change", x.input},
                    {"measured_rms_px", x.measured_rms_px},
                    {"model_rms_px", x.model_rms_px},
                    {"gain", x.gain},
                    {"after_gain_rms_px", x.after_gain_rms_px},
                    {"measured_mean_px", {x.measured_mean_px.x(), x.measured_mean_px.y()}},
                    {"model_mean_px", {x.model_mean_px.x(), x.model_mean_px.y()}}});
  j["responses"] = rows;
  j["surface_degree"] = a->degree;
  j["inputs_only_rmse_px"] = a->inputs_only_rmse_px;
  j["model_rmse_px"] = a->model_rmse_px;
  j["validation_marker_frames"] = a->validation_marker_frames;
  j["validation_frames"] = a->validation_frames;
  j["validation_frames_outside_calibration_range"] = a->validation_frames_outside;
  return j;
}

nlohmann::ordered_json structure_json(const ResidualStructure& s) {
  nlohmann::ordered_json cov = nlohmann::ordered_json::array();
  for (const auto& t : s.covariates) {
    nlohmann::ordered_json bins = nlohmann::ordered_json::array();
    for (std::size_t b = 0; b < t.labels.size(); ++b) {
      nlohmann::ordered_json bin = {{"bin", t.labels[b]}, {"rms_px", json_num(t.rms_px[b])}, {"count", t.count[b]}};
      if (t.contact_frame) {
        bin["mean_radial_px"] = json_num(t.mean_radial_px[b]);
        bin["mean_along_travel_px"] = json_num(t.mean_along_px[b]);
      }
      bins.push_back(bin);
    }
    cov.push_back({{"covariate", t.name}, {"unit", t.unit}, {"bins", bins}});
  }
  nlohmann::ordered_json mean = nlohmann::ordered_json::array(), pc1 = nlohmann::ordered_json::array();
  for (const auto& v : s.mean_field_px) mean.push_back({v.x(), v.y()});
  for (const auto& v : s.pc1_px) pc1.push_back({v.x(), v.y()});
  nlohmann::ordered_json binned = nlohmann::ordered_json::array();
  for (const auto& b : s.binned_fields) {
    nlohmann::ordered_json bins = nlohmann::ordered_json::array();
    for (std::size_t k = 0; k < b.labels.size(); ++k) {
      nlohmann::ordered_json field = nlohmann::ordered_json::array();
      for (const auto& v : b.mean_px[k]) field.push_back({v.x(), v.y()});
      bins.push_back({{"bin", b.labels[k]}, {"frames", b.frames[k]}, {"mean_px", field}});
    }
    binned.push_back({{"covariate", b.name}, {"bins", bins}});
  }
  return {{"rmse_px", json_num(s.rmse_px)},
          {"marker_frames", s.marker_frames},
          {"frames", s.frames},
          {"explained_variance_pc1_3", s.explained_variance},
          {"covariates", cov},
          {"mean_field_px", mean},
          {"pc1_px", pc1},
          {"binned_mean_fields", binned}};
}

nlohmann::ordered_json fingerprint_json(const FingerprintCheck& f) {
  nlohmann::ordered_json held = nlohmann::ordered_json::object(), band = nlohmann::ordered_json::object();
  for (const auto& [name, value] : f.held) held[name] = json_num(value);
  for (const auto& b : f.band) band[b.name] = {json_num(b.low), json_num(b.high)};
  return {{"evidence", f.evidence},
          {"param", f.param},
          {"calibration", json_num(f.calibration)},
          {"validation", json_num(f.validation)},
          {"signal_px", json_num(f.signal_px)},
          {"found", f.consistent},
          {"beyond_model_form", f.beyond_model_form},
          {"verdict", f.verdict},
          {"held_at", f.consistent ? held : nlohmann::ordered_json::object()},
          {"must_end_in", f.consistent ? band : nlohmann::ordered_json::object()}};
}

nlohmann::ordered_json candidate_json(const ResidualReport& r, const CandidateScore& c, std::size_t round,
                                      nlohmann::ordered_json* symptoms) {
  nlohmann::ordered_json cj;
  cj["effect"] = c.candidate;
  const EffectFit* f = report_format::fit_of(r, c.effect_ids);
  cj["params"] = f ? effect_params_json(f->fit.params, c.candidate) : nlohmann::ordered_json::object();
  add_score_json(c, &cj);
  if (std::isfinite(c.fingerprint_pct)) cj["held_drift_explained_pct"] = json_num(c.fingerprint_pct);
  if (c.fingerprint) cj["fingerprint"] = fingerprint_json(*c.fingerprint);
  if (!c.veto.empty()) cj["veto"] = c.veto;
  if (c.model_form_symptom) {
    cj["model_form_symptom"] = true;
    symptoms->push_back({{"effect", c.candidate},
                         {"round", round + 1},
                         {"veto", c.veto},
                         {"compensated_pct", json_num(c.improvement_pct)},
                         {"base_shifts", f ? base_shifts_json(r, *f) : nlohmann::ordered_json::object()}});
  }
  cj["fitted_with"] = c.effect_ids;
  return cj;
}

nlohmann::ordered_json model_forms_json(const ModelFormRound& m) {
  nlohmann::ordered_json forms = nlohmann::ordered_json::array();
  for (const auto& c : m.scores) {
    nlohmann::ordered_json cj;
    cj["model"] = c.candidate;
    add_score_json(c, &cj);
    cj["fit"] = metrics_json(m.fits.at(c.candidate));
    forms.push_back(cj);
  }
  return forms;
}

// Each selected effect with its evidence: found, or a correction of unshown cause (effect_evidence.hpp).
nlohmann::ordered_json selected_json(const ResidualReport& r) {
  nlohmann::ordered_json a = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < r.effects.selection.selected.size(); ++i) {
    const EffectEvidence* e = i < r.evidence.size() ? &r.evidence[i] : nullptr;
    a.push_back({{"effect", r.effects.selection.selected[i]},
                 {"fingerprint_found", e != nullptr && e->found},
                 {"evidence", e != nullptr ? e->looked_at + ": " + e->verdict : std::string("not read")}});
  }
  return a;
}

nlohmann::ordered_json at_bound_json(const std::vector<ParamAtBound>& b) {
  nlohmann::ordered_json a = nlohmann::ordered_json::array();
  for (const auto& p : b)
    a.push_back(
        {{"param", p.name}, {"value", p.value}, {"bound", p.upper ? "upper" : "lower"}, {"is_default", p.is_default}});
  return a;
}

}  // namespace

nlohmann::ordered_json base_shifts_json(const ResidualReport& r, const EffectFit& f) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  const ParamSet& before = r.effects.fits.at("").fit.params;
  for (std::size_t i = 0; i < before.size(); ++i) {
    const std::string& name = before.specs()[i].name;
    const int k = f.fit.params.index_of(name);
    if (k < 0) continue;
    const double a = before[i], b = f.fit.params[static_cast<std::size_t>(k)];
    if (std::abs(b - a) > 0.05 * std::max(std::abs(a), 1e-12)) j[name] = {a, b};
  }
  return j;
}

nlohmann::ordered_json residual_to_json(const ResidualReport& r) {
  nlohmann::ordered_json j;
  j["dataset"] = r.dataset;
  j["model"] = r.model_id;
  j["base_fitted"] = r.fit_base;
  j["search_calibration_samples"] = {{"fitted_on", r.search_samples}, {"of", r.calibration_samples}};
  j["structure_samples"] = {{"seen", r.structure_samples}, {"of", r.all_samples}};
  j["search_set_samples"] = {{"searched", r.search_set_samples}, {"of", r.all_samples}};
  j["after_model"] = r.after_model;
  j["before"] = metrics_json(r.before);
  j["after"] = metrics_json(r.after);
  if (!r.model_form.scores.empty()) {
    j["model_forms"] = model_forms_json(r.model_form);
    j["model_form_selected"] = r.model_form.selected;
    if (!r.model_form.held.empty()) {
      j["model_form_held"] = r.model_form.held;
      j["model_form_joint_rmse_px"] = r.model_form.joint_rmse_px;
    }
  }
  j["effects_on"] = r.effects.form;
  if (r.effects.final_refit) {
    j["final_refit"] = {
        {"rounds_rmse_px", report_format::rmse_of(r.effects.fits.at(effect_set_key(r.effects.selection.selected)))},
        {"refit_rmse_px", report_format::rmse_of(*r.effects.final_refit)},
        {"why", r.effects.final_refit_why},
        {"time_s", r.effects.final_refit->time_s}};
  }
  j["effects_reference"] = metrics_json(r.effects.fits.at(""));
  nlohmann::ordered_json cands = nlohmann::ordered_json::array(), symptoms = nlohmann::ordered_json::array(),
                         rounds = nlohmann::ordered_json::array();
  for (std::size_t round = 0; round < r.effects.selection.rounds.size(); ++round) {
    nlohmann::ordered_json rj = nlohmann::ordered_json::array();
    for (const auto& c : r.effects.selection.rounds[round]) rj.push_back(candidate_json(r, c, round, &symptoms));
    if (round == 0) cands = rj;
    rounds.push_back(rj);
  }
  j["candidates"] = cands;
  j["model_form_symptoms"] = symptoms;
  j["selected"] = selected_json(r);
  j["answer_labelled"] = labelled_answer(r);
  j["answer_at_bound"] = at_bound_json(r.answer_at_bound);
  nlohmann::ordered_json sel_params = nlohmann::ordered_json::object();
  for (const auto& id : r.effects.selection.selected) sel_params[id] = effect_params_json(r.after.fit.params, id);
  j["selected_params"] = sel_params;
  j["rounds"] = rounds;
  j["residual_before"] = structure_json(r.structure_before);
  j["residual_after"] = structure_json(r.structure_after);
  j["input_response_before"] = response_json(r.response_before);
  j["input_response_after"] = response_json(r.response_after);
  if (timings_in_outputs()) j["time_s"] = r.time_s;
  return j;
}

}  // namespace sb
