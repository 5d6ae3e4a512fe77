// Reports of the residual loop (residual.hpp): JSON, Markdown and PNG plots (OpenCV drawing).
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <tuple>

#include "core/base/error.hpp"
#include "core/base/format.hpp"
#include "core/base/reproducible.hpp"
#include "core/data/tsd.hpp"
#include "core/effects/effects.hpp"
#include "core/loop/residual.hpp"

namespace sb {

namespace {

// JSON has no NaN: empty metrics become null.
nlohmann::ordered_json num(double v) { return std::isfinite(v) ? nlohmann::ordered_json(v) : nullptr; }

// A candidate's score against the model it extends (effects and model forms alike).
void add_score_json(const CandidateScore& c, nlohmann::ordered_json* j) {
  (*j)["validation_rmse_px"] = num(c.rmse_px);
  (*j)["improvement_pct"] = num(c.improvement_pct);
  (*j)["ci95_pct"] = {num(c.improvement_ci_pct.low), num(c.improvement_ci_pct.high)};
  (*j)["delta_bic"] = num(c.delta_bic);
  (*j)["accepted"] = c.accepted;
  (*j)["reason"] = c.reason;
}

nlohmann::ordered_json metrics_json(const EffectFit& f) {
  nlohmann::ordered_json by = nlohmann::ordered_json::object();
  for (const auto& [motion, acc] : f.validation.per_motion) {
    const MetricsResult m = acc.result();
    by[motion] = {{"rmse_px", num(m.rmse_px)}, {"cs", num(m.cs)}, {"n", m.n}};
  }
  const MetricsResult all = f.validation.overall.result();
  nlohmann::ordered_json j;
  j["effects"] = f.effects;
  j["validation_rmse_px"] = num(all.rmse_px);
  j["validation_cs"] = num(all.cs);
  j["by_motion"] = by;
  j["calibration_rmse_px"] = num(std::sqrt(2 * f.fit.calibration_sse_px2 / f.fit.calibration_count));
  j["free_params"] = f.fit.free_params;
  if (f.fit.held_count > 0)
    j["held_drift"] = {{"marker_frames", f.fit.held_count},
                       {"measured_rms_px", num(std::sqrt(f.fit.held_signal_px2 / f.fit.held_count))},
                       {"error_rms_px", num(std::sqrt(f.fit.held_sse_px2 / f.fit.held_count))}};
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
      nlohmann::ordered_json bin = {{"bin", t.labels[b]}, {"rms_px", num(t.rms_px[b])}, {"count", t.count[b]}};
      if (t.contact_frame) {
        bin["mean_radial_px"] = num(t.mean_radial_px[b]);
        bin["mean_along_travel_px"] = num(t.mean_along_px[b]);
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
  return {{"rmse_px", num(s.rmse_px)},
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
  for (const auto& [name, value] : f.held) held[name] = num(value);
  for (const auto& b : f.band) band[b.name] = {num(b.low), num(b.high)};
  return {{"evidence", f.evidence},
          {"param", f.param},
          {"calibration", num(f.calibration)},
          {"validation", num(f.validation)},
          {"signal_px", num(f.signal_px)},
          {"found", f.consistent},
          {"beyond_model_form", f.beyond_model_form},
          {"verdict", f.verdict},
          {"held_at", f.consistent ? held : nlohmann::ordered_json::object()},
          {"must_end_in", f.consistent ? band : nlohmann::ordered_json::object()}};
}

const EffectFit* fit_of(const ResidualReport& r, const std::vector<std::string>& ids) {
  auto it = r.effects.fits.find(effect_set_key(ids));
  return it == r.effects.fits.end() ? nullptr : &it->second;
}

// ------------------------------------------------------------------ plots

const cv::Scalar kInk(40, 40, 40), kGrid(215, 215, 215), kBlue(200, 90, 30), kRed(40, 40, 210), kGrey(150, 150, 150);

void text(cv::Mat& img, const std::string& s, cv::Point p, double scale = 0.45, const cv::Scalar& c = kInk) {
  cv::putText(img, s, p, cv::FONT_HERSHEY_SIMPLEX, scale, c, 1, cv::LINE_AA);
}

// Axis labels and parameter values: three significant digits.
std::string g3(double v) { return format_number(v, "%.3g", "nan"); }

// RMS vs covariate: before (blue) and after (red) lines over the bins.
cv::Mat covariate_plot(const CovariateTable& before, const CovariateTable* after) {
  const int W = 480, H = 300, L = 60, R = 20, T = 30, B = 55;
  cv::Mat img(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
  double ymax = 0;
  for (double v : before.rms_px) ymax = std::isfinite(v) ? std::max(ymax, v) : ymax;
  if (after)
    for (double v : after->rms_px) ymax = std::isfinite(v) ? std::max(ymax, v) : ymax;
  ymax = ymax > 0 ? 1.1 * ymax : 1.0;
  const int n = static_cast<int>(before.labels.size());
  const auto px = [&](int b) { return L + (n <= 1 ? 0 : (W - L - R) * b / (n - 1)); };
  const auto py = [&](double v) { return static_cast<int>(H - B - (H - T - B) * v / ymax); };
  for (int g = 0; g <= 4; ++g) {
    const double v = ymax * g / 4;
    cv::line(img, {L, py(v)}, {W - R, py(v)}, kGrid);
    text(img, g3(v), {5, py(v) + 4}, 0.4);
  }
  cv::rectangle(img, {L, T}, {W - R, H - B}, kInk);
  const auto series = [&](const CovariateTable& t, const cv::Scalar& c) {
    cv::Point prev(-1, -1);
    for (int b = 0; b < n; ++b) {
      if (!std::isfinite(t.rms_px[b])) {
        prev = {-1, -1};
        continue;
      }
      const cv::Point p(px(b), py(t.rms_px[b]));
      cv::circle(img, p, 3, c, cv::FILLED, cv::LINE_AA);
      if (prev.x >= 0) cv::line(img, prev, p, c, 2, cv::LINE_AA);
      prev = p;
    }
  };
  series(before, kBlue);
  if (after) series(*after, kRed);
  for (int b = 0; b < n; ++b) {
    const std::string lab = before.unit.empty() ? before.labels[b] : g3(before.centre[b]);
    text(img, lab, {px(b) - 14, H - B + 16}, 0.38);
  }
  text(img, before.name + (before.unit.empty() ? "" : " (" + before.unit + ")"), {L, H - 12}, 0.5);
  text(img, "residual RMS (px)", {L, T - 10}, 0.5);
  text(img, "before", {W - 150, T - 10}, 0.45, kBlue);
  if (after) text(img, "after", {W - 80, T - 10}, 0.45, kRed);
  return img;
}

// Arrows of a per-marker field at the markers' image positions, scaled so the longest is 0.8 pitch (or, with
// `longest_px` > 0, an arrow that long: one scale for panels that are compared).
cv::Mat quiver_plot(const Sensor& sensor, const std::vector<Vec2>& field, const std::string& title,
                    double longest_px = 0) {
  const int S = 2, top = 40;
  const int W = sensor.camera.width_px * S, H = sensor.camera.height_px * S + top;
  cv::Mat img(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
  double longest = 0;
  for (const auto& v : field) longest = std::max(longest, v.norm());
  if (longest_px > 0) longest = longest_px;
  double pitch = std::numeric_limits<double>::infinity();
  const auto& m = sensor.markers_rest_px;
  for (std::size_t i = 1; i < m.size(); ++i) pitch = std::min(pitch, (m[i] - m[0]).norm());
  if (!std::isfinite(pitch) || pitch <= 0) pitch = 30;
  const double gain = longest > 0 ? 0.8 * pitch / longest : 0.0;
  for (std::size_t i = 0; i < m.size(); ++i) {
    const cv::Point2d p(m[i].x() * S, m[i].y() * S + top);
    cv::circle(img, p, 2, kGrey, cv::FILLED, cv::LINE_AA);
    const cv::Point2d q = p + cv::Point2d(field[i].x(), field[i].y()) * gain * S;
    if (field[i].norm() * gain > 0.5) cv::arrowedLine(img, p, q, kRed, 2, cv::LINE_AA, 0, 0.25);
  }
  text(img, title, {10, 18}, 0.55);
  text(img, "longest arrow = " + g3(longest) + " px (drawn x" + g3(gain) + ")", {10, 34}, 0.45, kGrey);
  return img;
}

void write_png(const std::string& path, const cv::Mat& img) {
  std::vector<unsigned char> buf;
  if (!cv::imencode(".png", img, buf)) throw InputError(path, "could not encode the plot");
  write_file_atomic(path, std::string(buf.begin(), buf.end()));
}

std::string slug(const std::string& s) {
  std::string o;
  for (char c : s) o += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return o;
}

// Tables: three decimals, a dash where a value is missing.
std::string f3(double v) { return format_number(v, "%.3f", "–"); }
double rmse_of(const EffectFit& f) { return f.validation.overall.result().rmse_px; }

// The contact-frame tables: where (relative to the contact edge, ahead of or behind the travel), when
// (phase) and under which load the model is wrong, and in which direction.
std::string contact_frame_markdown(const ResidualStructure& s) {
  std::string md =
      "### In the contact's own frame\n\nResidual (measured − model) of the marker-frames in contact; "
      "radial = along the direction from the contact centre to the marker (+ outward), along = along "
      "the indenter's travel since first contact (+ the way it moved). Mean components show a bias, "
      "RMS the size.\n\n";
  for (const auto& t : s.covariates) {
    if (!t.contact_frame) continue;
    md += "**" + t.name + (t.unit.empty() ? "" : " (" + t.unit + ")") +
          "**\n\n| bin | n | RMS px | mean radial px | mean along px |\n|---|---:|---:|---:|---:|\n";
    for (std::size_t b = 0; b < t.labels.size(); ++b)
      if (t.count[b] > 0)
        md += "| " + t.labels[b] + " | " + std::to_string(t.count[b]) + " | " + f3(t.rms_px[b]) + " | " +
              f3(t.mean_radial_px[b]) + " | " + f3(t.mean_along_px[b]) + " |\n";
    md += "\n";
  }
  return md;
}

}  // namespace

// The form's parameters a candidate's joint refit moved by more than 5 % from the form's fit: what the
// effect let the form stop doing (value before -> after).
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

namespace {

nlohmann::ordered_json candidate_json(const ResidualReport& r, const CandidateScore& c, std::size_t round,
                                      nlohmann::ordered_json* symptoms) {
  nlohmann::ordered_json cj;
  cj["effect"] = c.candidate;
  const EffectFit* f = fit_of(r, c.effect_ids);
  cj["params"] = f ? effect_params_json(f->fit.params, c.candidate) : nlohmann::ordered_json::object();
  add_score_json(c, &cj);
  if (std::isfinite(c.fingerprint_pct)) cj["held_drift_explained_pct"] = num(c.fingerprint_pct);
  if (c.fingerprint) cj["fingerprint"] = fingerprint_json(*c.fingerprint);
  if (!c.veto.empty()) cj["veto"] = c.veto;
  if (c.model_form_symptom) {
    cj["model_form_symptom"] = true;
    symptoms->push_back({{"effect", c.candidate},
                         {"round", round + 1},
                         {"veto", c.veto},
                         {"compensated_pct", num(c.improvement_pct)},
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

}  // namespace

namespace {

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

nlohmann::ordered_json residual_to_json(const ResidualReport& r) {
  nlohmann::ordered_json j;
  j["dataset"] = r.dataset;
  j["model"] = r.model_id;
  j["base_fitted"] = r.fit_base;
  j["search_calibration_samples"] = {{"fitted_on", r.search_samples}, {"of", r.calibration_samples}};
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
    j["final_refit"] = {{"rounds_rmse_px", rmse_of(r.effects.fits.at(effect_set_key(r.effects.selection.selected)))},
                        {"refit_rmse_px", rmse_of(*r.effects.final_refit)},
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

namespace {
// One row of quiver panels, a bin each, on one arrow scale (the longest mean arrow of any bin), halved in size.
cv::Mat binned_fields_plot(const Sensor& sensor, const BinnedMeanFields& b, const std::string& model_id) {
  double longest = 0;
  for (const auto& field : b.mean_px)
    for (const auto& v : field) longest = std::max(longest, v.norm());
  std::vector<cv::Mat> panels;
  for (std::size_t k = 0; k < b.labels.size(); ++k) {
    const std::string title = b.name + ": " + b.labels[k] + " (" + std::to_string(b.frames[k]) + " frames)";
    cv::Mat panel = quiver_plot(sensor, b.mean_px[k], title, longest);
    cv::resize(panel, panel, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
    panels.push_back(panel);
  }
  cv::Mat row;
  cv::hconcat(panels, row);
  cv::Mat header(28, row.cols, row.type(), cv::Scalar(255, 255, 255));
  text(header, "mean residual (measured - " + model_id + ") per bin of " + b.name + "; one arrow scale", {10, 19}, 0.5);
  cv::Mat out;
  cv::vconcat(header, row, out);
  return out;
}
}  // namespace

std::vector<std::string> write_residual_plots(const ResidualReport& r, const std::string& dir,
                                              const std::string& stem) {
  std::vector<std::string> names;
  const bool changed = r.after_model != r.model_id;
  for (std::size_t c = 0; c < r.structure_before.covariates.size(); ++c) {
    const auto& t = r.structure_before.covariates[c];
    const CovariateTable* after = changed && c < r.structure_after.covariates.size() ? &r.structure_after.covariates[c]
                                                                                     : nullptr;
    // The after table has its own bin edges; plot it only when they match the before table's.
    if (after && after->labels != t.labels) after = nullptr;
    const std::string name = stem + "_rms_vs_" + slug(t.name) + ".png";
    write_png((std::filesystem::path(dir) / name).string(), covariate_plot(t, after));
    names.push_back(name);
  }
  const auto pc1_title = [](const ResidualStructure& s) {
    return " PC1 (" + f3(100 * (s.explained_variance.empty() ? 0.0 : s.explained_variance[0])) + " % of variance)";
  };
  const std::vector<std::tuple<std::string, const ResidualStructure*, std::string>> fields = {
      {"mean_residual", &r.structure_before, "mean residual (measured - " + r.model_id + ")"},
      {"pc1", &r.structure_before, "residual" + pc1_title(r.structure_before)},
      {"mean_residual_after", &r.structure_after, "mean residual (measured - " + r.after_model + ")"}};
  for (const auto& [suffix, structure, title] : fields) {
    if (structure == &r.structure_after && !changed) continue;
    const std::string name = stem + "_" + suffix + ".png";
    write_png((std::filesystem::path(dir) / name).string(),
              quiver_plot(*r.sensor, suffix == "pc1" ? structure->pc1_px : structure->mean_field_px, title));
    names.push_back(name);
  }
  for (const auto& [structure, model, suffix] :
       {std::tuple{&r.structure_before, r.model_id, std::string()},
        std::tuple{&r.structure_after, r.after_model, std::string("_after")}}) {
    if (structure == &r.structure_after && !changed) continue;
    for (const auto& b : structure->binned_fields) {
      if (b.labels.empty()) continue;
      const std::string name = stem + "_mean_by_" + slug(b.name.substr(0, b.name.find(" ("))) + suffix + ".png";
      write_png((std::filesystem::path(dir) / name).string(), binned_fields_plot(*r.sensor, b, model));
      names.push_back(name);
    }
  }
  return names;
}

namespace {

// How the selected variant was fitted, when not simply jointly.
std::string held_note(const ModelFormRound& m) {
  if (m.held.empty()) return "";
  std::string names;
  for (const auto& n : m.held) names += (names.empty() ? "" : ", ") + n;
  return ", fitted with " + names + " held after their stage (the dilation kernel as the presses fit it; " +
         f3(m.joint_rmse_px) + " px when the joint refinement moves them too)";
}

// After a pose effect the rounds held the form's state and the pose, or the search fitted on a subset of the
// calibration samples; the answer is the final joint refit on all of them.
std::string final_refit_note(const EffectRounds& e) {
  if (!e.final_refit) return "";
  const EffectFit& rounds_fit = e.fits.at(effect_set_key(e.selection.selected));
  return "\n- fitted jointly once more after the rounds on every calibration sample (" + e.final_refit_why +
         "): validation " + f3(rmse_of(rounds_fit)) + " px as the rounds fitted it, " + f3(rmse_of(*e.final_refit)) +
         " px refitted (the answer's)";
}

// The search's costly fits on a subset of the calibration split (ResidualOptions::search_samples).
std::string search_subset_note(const ResidualReport& r) {
  if (r.search_samples >= r.calibration_samples) return "";
  return "The search's fits that rerun the form on every run (model-form variants, pose effects, joint refits) saw " +
         std::to_string(r.search_samples) + " of the " + std::to_string(r.calibration_samples) +
         " calibration samples, evenly spaced; every score uses all samples of both splits, and the answer is "
         "refitted on the whole calibration split.\n\n";
}

// Which of the answer's effects are found by their evidence and which are corrections of unshown cause.
std::string evidence_headline(const ResidualReport& r) {
  if (r.evidence.empty()) return "";
  const auto found = effects_by_evidence(r, true), unshown = effects_by_evidence(r, false);
  std::string h = " — found: " + (found.empty() ? std::string("none") : effect_set_key(found));
  if (!unshown.empty()) h += "; correction of unshown cause: " + effect_set_key(unshown);
  return h;
}

std::string evidence_markdown(const ResidualReport& r) {
  std::string md;
  for (const auto& e : r.evidence)
    md += "- **" + e.effect + (e.found ? "** found by its evidence" : "** a correction of unshown cause") + " — " +
          e.looked_at + ": " + e.verdict + "\n";
  if (!md.empty() && !effects_by_evidence(r, false).empty())
    md +=
        "\nA correction of unshown cause lowers the held-out error, but nothing outside that gain shows the effect "
        "is why: read it as a correction the model's form needs, not as a measured property of the sensor "
        "(docs/effects.md).\n";
  return md;
}

// The answer's own parameters at a bound: model-form symptoms of the answer, not only of rejected candidates.
std::string answer_bounds_markdown(const ResidualReport& r) {
  if (r.answer_at_bound.empty()) return "";
  std::string md = "\nModel-form symptoms in the answer (free parameters at a bound of their range):\n\n";
  for (const auto& b : r.answer_at_bound)
    md += "- `" + b.name + "` = " + g3(b.value) + " at its " + (b.upper ? "upper" : "lower") + " bound" +
          (b.is_default ? " (its no-effect default: the term switched itself off)" : "") + "\n";
  return md;
}

// The answer first: the model the loop ends with, and how it got there.
std::string answer_markdown(const ResidualReport& r) {
  std::string md = "## The loop's answer: `" + r.after_model + "`" + evidence_headline(r) + "\n\n";
  md += "Validation RMSE " + f3(rmse_of(r.before)) + " px (" + r.model_id + " as fitted) -> **" + f3(rmse_of(r.after)) +
        " px** (" + r.after_model + ", fitted jointly)";
  const double change = 100.0 * (rmse_of(r.after) - rmse_of(r.before)) / rmse_of(r.before);
  md += std::isfinite(change) ? ", " + format_number(change, "%+.1f") + " %.\n\n" : ".\n\n";
  md += "- model form: " +
        (r.model_form.selected.empty() ? std::string(r.model_form.scores.empty() ? "not tried" : "none selected")
                                       : r.model_form.selected + held_note(r.model_form)) +
        "\n";
  md += "- effects on " + r.effects.form + ": " +
        (r.effects.selection.selected.empty() ? std::string("none selected")
                                              : effect_set_key(r.effects.selection.selected)) +
        final_refit_note(r.effects) + "\n" + evidence_markdown(r) + answer_bounds_markdown(r) +
        "\nLoad it anywhere as `--model " + r.after_model +
        "` with the parameter file written beside this report "
        "(`--params`), or open this report in the workbench.\n\n";
  return md;
}

// Per bin of depth, travel and tilt direction: the mean residual's size and its mean over the markers (a shift of
// the whole field shows there), beside the maps (write_residual_plots).
std::string binned_fields_markdown(const ResidualStructure& sb) {
  if (sb.binned_fields.empty()) return "";
  std::string md =
      "### The mean residual per bin (maps: the `mean_by_` plots below)\n\n"
      "| covariate | bin | frames | RMS of the mean px | mean over markers px | largest arrow px "
      "|\n|---|---|---:|---:|---|---:|\n";
  for (const auto& b : sb.binned_fields)
    for (std::size_t k = 0; k < b.labels.size(); ++k) {
      if (b.frames[k] == 0) continue;
      const FieldSummary f = summarise_field(b.mean_px[k]);
      md += "| " + b.name + " | " + b.labels[k] + " | " + std::to_string(b.frames[k]) + " | " + f3(f.rms_px) + " | (" +
            format_number(f.shift_px.x(), "%.2f") + ", " + format_number(f.shift_px.y(), "%.2f") + ") | " +
            f3(f.longest_px) + " |\n";
    }
  return md + "\n";
}

std::string structure_markdown(const ResidualStructure& sb, const std::vector<std::string>& plots) {
  std::string md = "## What the residual looked like\n\n";
  md += "Base residual RMS " + f3(sb.rmse_px) + " px over " + std::to_string(sb.marker_frames) + " marker-frames (" +
        std::to_string(sb.frames) +
        " frames, calibration + validation). Principal components of the centred residual "
        "(frames × 2·markers) explain ";
  for (std::size_t c = 0; c < sb.explained_variance.size(); ++c)
    md += (c ? ", " : "") + std::string("PC") + std::to_string(c + 1) + " " + f3(100 * sb.explained_variance[c]) + " %";
  md += " of its variance.\n\n";
  double mean_norm = 0;
  for (const auto& v : sb.mean_field_px) mean_norm = std::max(mean_norm, v.norm());
  md += "Largest mean-residual arrow: " + f3(mean_norm) + " px.\n\n";
  md += contact_frame_markdown(sb);
  md += binned_fields_markdown(sb);
  for (const auto& t : sb.covariates) {
    if (t.contact_frame) continue;
    md += "**" + t.name + (t.unit.empty() ? "" : " (" + t.unit + ")") + "** — RMS px per bin: ";
    for (std::size_t b = 0; b < t.labels.size(); ++b)
      md += (b ? " · " : "") + t.labels[b] + ": " + f3(t.rms_px[b]) + " (n " + std::to_string(t.count[b]) + ")";
    md += "\n\n";
  }
  for (const auto& p : plots) md += "![" + p + "](" + p + ")\n";
  return md;
}

// The measured field's and the models' responses to the known inputs (input_response.hpp).
std::string response_markdown(const ResidualReport& r) {
  if (!r.response_before) return "";
  std::string md = "\n## How the field responds to the known inputs\n\n" +
                   input_response_markdown(*r.response_before, r.model_id);
  if (r.response_after) md += "\nThe loop's answer:\n\n" + input_response_markdown(*r.response_after, r.after_model);
  return md;
}

// The model-form round: the base model's variants, each a model of its own, against the base.
std::string model_form_markdown(const ResidualReport& r) {
  const ModelFormRound& m = r.model_form;
  if (m.scores.empty()) return "";
  std::string md = "\n## Which model form explains it\n\n";
  md += "Each model-form variant of " + r.model_id +
        " (docs/effects.md, \"Model-form effects\") fitted like the base "
        "(its stages, then jointly) on calibration, scored on validation with the same rule as the effects: the 95 % "
        "paired-bootstrap interval of the improvement above the margin and a better calibration BIC.\n\n"
        "| model | val. RMSE px | improvement % | 95 % CI % | ΔBIC | accepted |\n|---|---|---|---|---|---|\n";
  for (const auto& c : m.scores)
    md += "| " + c.candidate + " | " + f3(c.rmse_px) + " | " + f3(c.improvement_pct) + " | [" +
          f3(c.improvement_ci_pct.low) + ", " + f3(c.improvement_ci_pct.high) + "] | " + f3(c.delta_bic) + " | " +
          (c.accepted ? "yes" : "no") + " |\n";
  md += "\n" +
        (m.selected.empty()
             ? std::string("**No model form selected**: no variant passes the rule; the effect rounds below run on ") +
                   r.model_id + "."
             : "**Selected model form: " + m.selected + "** (" + f3(m.scores.front().reference_rmse_px) + " -> " +
                   f3(validation_rmse(m.fits.at(m.selected).fit.validation)) + " px validation)" + held_note(m) +
                   ". The effect rounds below run on it.") +
        "\n";
  return md;
}

std::string round_table_markdown(const ResidualReport& r, const std::vector<CandidateScore>& row) {
  std::string md =
      "| effect | val. RMSE px | improvement % | 95 % CI % | ΔBIC | accepted | parameters |\n"
      "|---|---|---|---|---|---|---|\n";
  for (const auto& c : row) {
    const EffectFit* f = fit_of(r, c.effect_ids);
    std::string params;
    if (f) {
      const auto pj = effect_params_json(f->fit.params, c.candidate);  // items() must not outlive it
      for (const auto& [k, v] : pj.items()) params += (params.empty() ? "" : ", ") + k + " = " + g3(v.get<double>());
    }
    md += "| " + c.candidate + " | " + f3(c.rmse_px) + " | " + f3(c.improvement_pct) + " | [" +
          f3(c.improvement_ci_pct.low) + ", " + f3(c.improvement_ci_pct.high) + "] | " + f3(c.delta_bic) + " | " +
          (c.accepted ? "yes" : "no") + " | " + params + " |\n";
  }
  return md + "\n";
}

std::string symptoms_markdown(const ResidualReport& r, const std::vector<CandidateScore>& row) {
  std::string md;
  for (const auto& c : row) {
    if (!c.model_form_symptom) continue;
    const EffectFit* f = fit_of(r, c.effect_ids);
    const std::string prefix = "model-form symptom: ";
    const std::string why = c.veto.rfind(prefix, 0) == 0 ? c.veto.substr(prefix.size()) : c.veto;
    md += "- **Model-form symptom: " + c.candidate + "** (not selected) — " + why + "; it bought " +
          f3(c.improvement_pct) + " % on validation";
    if (f) {
      const auto shifts = base_shifts_json(r, *f);
      std::string moved;
      for (const auto& [k, v] : shifts.items())
        moved += (moved.empty() ? "" : ", ") + k + " " + g3(v[0].get<double>()) + " → " + g3(v[1].get<double>());
      if (!moved.empty()) md += ", with the form refitted (" + moved + ")";
    }
    md += ". The effect was compensating the model's form, not measuring its own physics.\n";
  }
  return md + "\n";
}

std::string fingerprints_markdown(const std::vector<CandidateScore>& row) {
  std::string md;
  for (const auto& c : row) {
    if (!c.fingerprint) continue;
    if (md.empty()) md += "Fingerprints (each estimated on the calibration and, as a check, the validation split):\n\n";
    const FingerprintCheck& f = *c.fingerprint;
    md += "- **" + c.candidate + "** — " + f.evidence + ": `" + f.param + "` " + g3(f.calibration) + " / " +
          g3(f.validation) + " (evidence " + f3(f.signal_px) + " px); " + f.verdict;
    if (f.consistent) {
      std::string how;
      for (const auto& [name, value] : f.held) how += (how.empty() ? "" : ", ") + name + " held at " + g3(value);
      for (const auto& b : f.band)
        how += (how.empty() ? "" : ", ") + b.name + " required to end in [" + g3(b.low) + ", " + g3(b.high) + "]";
      md += "; fitted with " + how;
    }
    md += std::string(" → ") + (c.accepted ? "**accepted**" : "not accepted") + ": " +
          c.reason.substr(c.reason.find(": ") + 2) + ".\n";
  }
  return md.empty() ? md : md + "\n";
}

std::string selected_markdown(const ResidualReport& r) {
  const auto& selected = r.effects.selection.selected;
  if (selected.empty())
    return "**Selected: nothing.** No catalogued effect improves the validation error of " + r.effects.form +
           " reliably at this data size; the rest of its residual is not attributed.\n\n";
  std::string md = "**Selected: " + effect_set_key(selected) + "** on " + r.effects.form + " (" + labelled_answer(r) +
                   "). Parameters fitted:\n\n";
  bool any_bound = false;
  for (const auto& id : selected) {
    const auto pj = effect_params_json(r.after.fit.params, id);
    for (const auto& [k, v] : pj.items()) {
      md += "- `" + id + "." + k + "` = " + g3(v.get<double>());
      const ParamSpec& spec = r.after.fit.params.specs()[r.after.fit.params.index_of(id + kEffectParamSeparator + k)];
      const bool at_min = v.get<double>() <= spec.min, at_max = v.get<double>() >= spec.max;
      if (at_min || at_max) md += std::string(" **(at its ") + (at_min ? "lower" : "upper") + " bound)**";
      any_bound = any_bound || at_min || at_max;
      md += "\n";
    }
  }
  if (any_bound)
    md +=
        "\nA parameter at its bound means the data ask for more than the effect's physical range: the "
        "effect is standing in for something the model lacks rather than measuring that physics.\n";
  return md + "\n";
}

std::string effects_markdown(const ResidualReport& r) {
  std::string md = "\n## Which effect explains it\n\n";
  md += "Each catalogued effect was wrapped around " + r.effects.form +
        " (the model form the round above ended with) "
        "and fitted alone over its recorded field, then (unless screened: too small a gain alone, or not among the "
        "round's "
        "few best alone) jointly with it on calibration; accepted "
        "when the 95 % paired-bootstrap interval of the validation improvement lies above the margin (or the effect "
        "explains the held drift) and the calibration BIC improves, and vetoed when a parameter sits at a bound of its "
        "range (docs/effects.md).\n\n";
  for (std::size_t round = 0; round < r.effects.selection.rounds.size(); ++round) {
    auto row = r.effects.selection.rounds[round];
    std::sort(row.begin(), row.end(), [](auto& a, auto& b) { return a.improvement_pct > b.improvement_pct; });
    md += "Round " + std::to_string(round + 1) + ":\n\n" + round_table_markdown(r, row) + symptoms_markdown(r, row) +
          fingerprints_markdown(row);
  }
  return md + selected_markdown(r);
}

std::string errors_markdown(const ResidualReport& r) {
  std::string md = "## Error before and after (validation)\n\nBefore: " + r.model_id +
                   " as fitted. After: " + r.after_model +
                   ".\n\n| motion | RMSE before px | RMSE after px | CS before | CS after |\n"
                   "|---|---|---|---|---|\n";
  for (const auto& [motion, acc] : r.before.validation.per_motion) {
    const MetricsResult b = acc.result();
    auto it = r.after.validation.per_motion.find(motion);
    const MetricsResult a = it == r.after.validation.per_motion.end() ? MetricsResult{} : it->second.result();
    md += "| " + motion + " | " + f3(b.rmse_px) + " | " + f3(a.rmse_px) + " | " + f3(b.cs) + " | " + f3(a.cs) + " |\n";
  }
  const MetricsResult b = r.before.validation.overall.result(), a = r.after.validation.overall.result();
  return md + "| **all** | " + f3(b.rmse_px) + " | " + f3(a.rmse_px) + " | " + f3(b.cs) + " | " + f3(a.cs) + " |\n\n";
}

}  // namespace

std::string residual_to_markdown(const ResidualReport& r, const std::vector<std::string>& plots) {
  std::string md = "# Residual attribution: " + r.model_id + " on " + r.dataset + "\n\n";
  md += std::string("Base model ") +
        (r.fit_base ? "fitted on the calibration split (staged + joint)" : "with the given parameters (not refitted)") +
        "; scores on the validation split. Residual = measured − predicted.\n\n" + search_subset_note(r);
  md += answer_markdown(r) + structure_markdown(r.structure_before, plots) + response_markdown(r) +
        model_form_markdown(r) + effects_markdown(r) + errors_markdown(r);
  if (timings_in_outputs()) md += "Run time " + f3(r.time_s) + " s.\n";
  return md;
}

}  // namespace sb
