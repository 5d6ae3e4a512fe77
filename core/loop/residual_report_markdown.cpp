// The residual loop's report as Markdown (residual_report.hpp).
#include <algorithm>
#include <cmath>

#include "core/base/format.hpp"
#include "core/base/reproducible.hpp"
#include "core/effects/effects.hpp"
#include "core/loop/residual_report.hpp"
#include "core/loop/residual_report_format.hpp"

namespace sb {

namespace {

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
        md += "| " + t.labels[b] + " | " + std::to_string(t.count[b]) + " | " + report_format::f3(t.rms_px[b]) + " | " +
              report_format::f3(t.mean_radial_px[b]) + " | " + report_format::f3(t.mean_along_px[b]) + " |\n";
    md += "\n";
  }
  return md;
}

// How the selected variant was fitted, when not simply jointly.
std::string held_note(const ModelFormRound& m) {
  if (m.held.empty()) return "";
  std::string names;
  for (const auto& n : m.held) names += (names.empty() ? "" : ", ") + n;
  return ", fitted with " + names + " held after their stage (the dilation kernel as the presses fit it; " +
         report_format::f3(m.joint_rmse_px) + " px when the joint refinement moves them too)";
}

// After a pose effect the rounds held the form's state and the pose, or the search fitted on a subset of the
// calibration samples; the answer is the final joint refit on all of them.
std::string final_refit_note(const EffectRounds& e) {
  if (!e.final_refit) return "";
  const EffectFit& rounds_fit = e.fits.at(effect_set_key(e.selection.selected));
  return "\n- fitted jointly once more after the rounds on every calibration sample (" + e.final_refit_why +
         "): validation " + report_format::f3(report_format::rmse_of(rounds_fit)) + " px as the rounds fitted it, " +
         report_format::f3(report_format::rmse_of(*e.final_refit)) + " px refitted (the answer's)";
}

// The search's costly fits on a subset of the calibration split (ResidualOptions::search_samples).
std::string search_subset_note(const ResidualReport& r) {
  std::string s;
  if (r.search_set_samples != 0 && r.search_set_samples < r.all_samples)
    s = "The search (the model-form round and the effect rounds: their fits, scores, fingerprints and bootstraps) "
        "saw " +
        std::to_string(r.search_set_samples) + " of the " + std::to_string(r.all_samples) +
        " samples, evenly spaced over each split; its tables' scores are on those, and so are the responses to "
        "the inputs. The base and the answer were then refitted jointly on the whole calibration split; their "
        "errors and the evidence below are over every sample.\n\n";
  if (r.search_samples < r.calibration_samples)
    s += "The search's fits that rerun the form on every run (model-form variants, pose effects, joint refits) saw " +
         std::to_string(r.search_samples) + " of the " + std::to_string(r.calibration_samples) +
         " calibration samples, evenly spaced; every score of the search uses all of " +
         (s.empty() ? std::string("the samples of both splits") : std::string("its samples")) +
         ", and the answer is refitted on the whole calibration split.\n\n";
  if (r.structure_samples < r.all_samples)
    s += "The residual structure below (its tables, components and binned fields) describes " +
         std::to_string(r.structure_samples) + " of the " + std::to_string(r.all_samples) +
         " samples, evenly spaced over each split; the errors before and after are over all of them.\n\n";
  return s;
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
    md += "- `" + b.name + "` = " + report_format::g3(b.value) + " at its " + (b.upper ? "upper" : "lower") + " bound" +
          (b.is_default ? " (its no-effect default: the term switched itself off)" : "") + "\n";
  return md;
}

// The answer first: the model the loop ends with, and how it got there.
std::string answer_markdown(const ResidualReport& r) {
  std::string md = "## The loop's answer: `" + r.after_model + "`" + evidence_headline(r) + "\n\n";
  md += "Validation RMSE " + report_format::f3(report_format::rmse_of(r.before)) + " px (" + r.model_id +
        " as fitted) -> **" + report_format::f3(report_format::rmse_of(r.after)) + " px** (" + r.after_model +
        ", fitted jointly)";
  const double change = 100.0 * (report_format::rmse_of(r.after) - report_format::rmse_of(r.before)) /
                        report_format::rmse_of(r.before);
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
      md += "| " + b.name + " | " + b.labels[k] + " | " + std::to_string(b.frames[k]) + " | " +
            report_format::f3(f.rms_px) + " | (" + format_number(f.shift_px.x(), "%.2f") + ", " +
            format_number(f.shift_px.y(), "%.2f") + ") | " + report_format::f3(f.longest_px) + " |\n";
    }
  return md + "\n";
}

std::string structure_markdown(const ResidualStructure& sb, const std::vector<std::string>& plots) {
  std::string md = "## What the residual looked like\n\n";
  md += "Base residual RMS " + report_format::f3(sb.rmse_px) + " px over " + std::to_string(sb.marker_frames) +
        " marker-frames (" + std::to_string(sb.frames) +
        " frames, calibration + validation). Principal components of the centred residual "
        "(frames × 2·markers) explain ";
  for (std::size_t c = 0; c < sb.explained_variance.size(); ++c)
    md += (c ? ", " : "") + std::string("PC") + std::to_string(c + 1) + " " +
          report_format::f3(100 * sb.explained_variance[c]) + " %";
  md += " of its variance.\n\n";
  double mean_norm = 0;
  for (const auto& v : sb.mean_field_px) mean_norm = std::max(mean_norm, v.norm());
  md += "Largest mean-residual arrow: " + report_format::f3(mean_norm) + " px.\n\n";
  md += contact_frame_markdown(sb);
  md += binned_fields_markdown(sb);
  for (const auto& t : sb.covariates) {
    if (t.contact_frame) continue;
    md += "**" + t.name + (t.unit.empty() ? "" : " (" + t.unit + ")") + "** — RMS px per bin: ";
    for (std::size_t b = 0; b < t.labels.size(); ++b)
      md += (b ? " · " : "") + t.labels[b] + ": " + report_format::f3(t.rms_px[b]) + " (n " +
            std::to_string(t.count[b]) + ")";
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
    md += "| " + c.candidate + " | " + report_format::f3(c.rmse_px) + " | " + report_format::f3(c.improvement_pct) +
          " | [" + report_format::f3(c.improvement_ci_pct.low) + ", " + report_format::f3(c.improvement_ci_pct.high) +
          "] | " + report_format::f3(c.delta_bic) + " | " + (c.accepted ? "yes" : "no") + " |\n";
  md += "\n" +
        (m.selected.empty()
             ? std::string("**No model form selected**: no variant passes the rule; the effect rounds below run on ") +
                   r.model_id + "."
             : "**Selected model form: " + m.selected + "** (" + report_format::f3(m.scores.front().reference_rmse_px) +
                   " -> " + report_format::f3(validation_rmse(m.fits.at(m.selected).fit.validation)) +
                   " px validation)" + held_note(m) + ". The effect rounds below run on it.") +
        "\n";
  return md;
}

std::string round_table_markdown(const ResidualReport& r, const std::vector<CandidateScore>& row) {
  std::string md =
      "| effect | val. RMSE px | improvement % | 95 % CI % | ΔBIC | accepted | parameters |\n"
      "|---|---|---|---|---|---|---|\n";
  for (const auto& c : row) {
    const EffectFit* f = report_format::fit_of(r, c.effect_ids);
    std::string params;
    if (f) {
      const auto pj = effect_params_json(f->fit.params, c.candidate);  // items() must not outlive it
      for (const auto& [k, v] : pj.items())
        params += (params.empty() ? "" : ", ") + k + " = " + report_format::g3(v.get<double>());
    }
    md += "| " + c.candidate + " | " + report_format::f3(c.rmse_px) + " | " + report_format::f3(c.improvement_pct) +
          " | [" + report_format::f3(c.improvement_ci_pct.low) + ", " + report_format::f3(c.improvement_ci_pct.high) +
          "] | " + report_format::f3(c.delta_bic) + " | " + (c.accepted ? "yes" : "no") + " | " + params + " |\n";
  }
  return md + "\n";
}

std::string symptoms_markdown(const ResidualReport& r, const std::vector<CandidateScore>& row) {
  std::string md;
  for (const auto& c : row) {
    if (!c.model_form_symptom) continue;
    const EffectFit* f = report_format::fit_of(r, c.effect_ids);
    const std::string prefix = "model-form symptom: ";
    const std::string why = c.veto.rfind(prefix, 0) == 0 ? c.veto.substr(prefix.size()) : c.veto;
    md += "- **Model-form symptom: " + c.candidate + "** (not selected) — " + why + "; it bought " +
          report_format::f3(c.improvement_pct) + " % on validation";
    if (f) {
      const auto shifts = base_shifts_json(r, *f);
      std::string moved;
      for (const auto& [k, v] : shifts.items())
        moved += (moved.empty() ? "" : ", ") + k + " " + report_format::g3(v[0].get<double>()) + " → " +
                 report_format::g3(v[1].get<double>());
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
    md += "- **" + c.candidate + "** — " + f.evidence + ": `" + f.param + "` " + report_format::g3(f.calibration) +
          " / " + report_format::g3(f.validation) + " (evidence " + report_format::f3(f.signal_px) + " px); " +
          f.verdict;
    if (f.consistent) {
      std::string how;
      for (const auto& [name, value] : f.held)
        how += (how.empty() ? "" : ", ") + name + " held at " + report_format::g3(value);
      for (const auto& b : f.band)
        how += (how.empty() ? "" : ", ") + b.name + " required to end in [" + report_format::g3(b.low) + ", " +
               report_format::g3(b.high) + "]";
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
      md += "- `" + id + "." + k + "` = " + report_format::g3(v.get<double>());
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
    md += "| " + motion + " | " + report_format::f3(b.rmse_px) + " | " + report_format::f3(a.rmse_px) + " | " +
          report_format::f3(b.cs) + " | " + report_format::f3(a.cs) + " |\n";
  }
  const MetricsResult b = r.before.validation.overall.result(), a = r.after.validation.overall.result();
  return md + "| **all** | " + report_format::f3(b.rmse_px) + " | " + report_format::f3(a.rmse_px) + " | " +
         report_format::f3(b.cs) + " | " + report_format::f3(a.cs) + " |\n\n";
}

}  // namespace

std::string residual_to_markdown(const ResidualReport& r, const std::vector<std::string>& plots) {
  std::string md = "# Residual attribution: " + r.model_id + " on " + r.dataset + "\n\n";
  md += std::string("Base model ") +
        (r.fit_base ? "fitted on the calibration split (staged + joint)" : "with the given parameters (not refitted)") +
        "; scores on the validation split. Residual = measured − predicted.\n\n" + search_subset_note(r);
  md += answer_markdown(r) + structure_markdown(r.structure_before, plots) + response_markdown(r) +
        model_form_markdown(r) + effects_markdown(r) + errors_markdown(r);
  if (timings_in_outputs()) md += "Run time " + report_format::f3(r.time_s) + " s.\n";
  return md;
}

}  // namespace sb
