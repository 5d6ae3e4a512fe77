// The residual loop's pipeline (residual.hpp): fit_base, model_form_round, effect_rounds, final_fit, score.
#include "core/loop/residual.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "core/base/elapsed.hpp"
#include "core/effects/effects.hpp"
#include "core/effects/model_spec.hpp"
#include "core/loop/effect_evidence.hpp"
#include "core/loop/effect_search.hpp"
#include "core/models/model_family.hpp"

namespace sb {

namespace {
// The family whose base form `model_id` is, or nullptr (a correction, a form with effects, an unknown id).
const ModelFamily* family_based_on(const std::string& model_id) {
  const ModelFamily* family = find_model_family_of_form(model_id);
  return family != nullptr && family->base().id == model_id ? family : nullptr;
}
}  // namespace

std::vector<std::string> model_form_variants(const std::string& model_id) {
  const ModelFamily* family = family_based_on(model_id);
  return family != nullptr ? family->correction_ids() : std::vector<std::string>{};
}

std::vector<std::string> model_form_hold(const std::string& model_id) {
  const ModelFamily* family = family_based_on(model_id);
  return family != nullptr ? family->hold : std::vector<std::string>{};
}

std::vector<ParamAtBound> params_at_bounds(const ParamSet& params, const std::vector<std::string>& free) {
  // Closer to a bound than this fraction of the range (of the log range for log-scale specs) is at it.
  constexpr double kAtBoundFraction = 0.005;
  std::vector<ParamAtBound> out;
  for (const auto& name : free) {
    const int i = params.index_of(name);
    if (i < 0) continue;
    const ParamSpec& sp = params.specs()[static_cast<std::size_t>(i)];
    const double v = params[static_cast<std::size_t>(i)];
    const bool lg = sp.log_scale && sp.min > 0;
    const auto x = [&](double u) { return lg ? std::log(u) : u; };
    const double tol = kAtBoundFraction * (x(sp.max) - x(sp.min));
    for (const double b : {sp.min, sp.max})
      if (std::abs(x(v) - x(b)) <= tol) {
        out.push_back({name, v, b == sp.max, b == sp.default_value});
        break;
      }
  }
  return out;
}

std::vector<std::string> effects_by_evidence(const ResidualReport& r, bool found) {
  std::vector<std::string> out;
  for (const auto& e : r.evidence)
    if (e.found == found) out.push_back(e.effect);
  return out;
}

std::string labelled_answer(const ResidualReport& r) {
  std::string s = r.effects.form;
  for (const auto& e : r.evidence) s += " + " + e.effect + (e.found ? " (found)" : " (correction of unshown cause)");
  return s;
}

std::string effect_set_key(const std::vector<std::string>& ids) {
  std::string k;
  for (const auto& id : ids) k += (k.empty() ? "" : "+") + id;
  return k;
}

namespace {

// A split's share of `cap` samples of `all` (both splits), at least one; the split whole when cap is 0 or >= all.
std::size_t split_share(std::size_t split, std::size_t cap, std::size_t all) {
  return cap == 0 || cap >= all ? split : std::max<std::size_t>(1, cap * split / all);
}

// ResidualOptions::structure_samples of both splits: each split's share of `cap`, evenly spaced (evenly_spaced).
std::vector<const FitSample*> structure_subset(const ResidualInputs& in, std::size_t cap) {
  const std::size_t all = in.calibration.size() + in.validation.size();
  std::vector<const FitSample*> out;
  for (const auto* split : {&in.calibration, &in.validation}) {
    for (std::size_t i : evenly_spaced(split->size(), split_share(split->size(), cap, all)))
      out.push_back(&(*split)[i]);
  }
  return out;
}

// ResidualOptions::search_set's samples of both splits (evenly spaced shares), or nullopt when that is all of them.
std::optional<ResidualInputs> search_set_of(const ResidualInputs& in, std::size_t cap) {
  const std::size_t all = in.calibration.size() + in.validation.size();
  if (cap == 0 || cap >= all) return std::nullopt;
  ResidualInputs s;
  s.dataset = in.dataset;
  s.model_id = in.model_id;
  s.sensor = in.sensor;
  s.base_params = in.base_params;
  const auto share = [&](const std::vector<FitSample>& split) {
    return subset(split, evenly_spaced(split.size(), split_share(split.size(), cap, all)));
  };
  s.calibration = share(in.calibration);
  s.validation = share(in.validation);
  return s;
}

// True when some pose turns the indenter's approach axis (+z) away from E's (Effect::needs_tilt).
bool any_tilt(const ResidualInputs& in) {
  constexpr double kTiltRad = 1e-6;
  for (const auto* split : {&in.calibration, &in.validation})
    for (const FitSample& s : *split)
      for (const Pose& X : s.X_EI)
        if ((X.linear() * Vec3::UnitZ() - Vec3::UnitZ()).norm() > kTiltRad) return true;
  return false;
}

// Every catalogued effect that can change this data's model: not one that is the identity on this sensor
// (Effect::acts_on) or on a set without tilt (Effect::needs_tilt); the caller's list when it gives one.
std::vector<std::string> default_candidates(const ResidualInputs& in) {
  std::vector<std::string> out = effect_ids();
  const bool tilted = any_tilt(in);
  std::erase_if(out, [&](const std::string& id) {
    const auto e = make_effect(id);
    return !e->acts_on(*in.sensor) || (e->needs_tilt() && !tilted);
  });
  return out;
}

}  // namespace

ResidualLoop::ResidualLoop(const ResidualInputs& in, const ResidualOptions& options)
    : in_(in),
      o_(options),
      candidates_(options.candidates.empty() ? default_candidates(in) : options.candidates),
      search_set_(search_set_of(in, options.search_set)),
      search_cal_(
          subset(search_in().calibration, evenly_spaced(search_in().calibration.size(), options.search_samples))),
      structure_samples_(structure_subset(in, options.structure_samples)) {
  if (in.calibration.empty()) throw std::invalid_argument("residual: no calibration samples");
  if (in.validation.empty()) throw std::invalid_argument("residual: no validation samples");
  default_params(in.model_id);                         // an unknown model fails before any work
  for (const auto& id : candidates_) make_effect(id);  // so does an unknown effect
}

FitOptions ResidualLoop::fit_options() const {
  FitOptions fo;
  fo.max_iterations = o_.max_iterations;
  fo.cancel = o_.progress.cancel;
  fo.joint = true;
  return fo;
}

EffectFit ResidualLoop::scored(const std::string& model_id, std::vector<std::string> effects, const ParamSet& params,
                               std::size_t free_params) const {
  const SampleModelFactory make = spec_model_factory(model_id, in_.sensor);
  return score_fit(search_in(), std::move(effects), params, free_params, make, make);
}

EffectFit ResidualLoop::scored_on_all(const std::string& model_id, std::vector<std::string> effects,
                                      const ParamSet& params, std::size_t free_params) const {
  const SampleModelFactory make = spec_model_factory(model_id, in_.sensor);
  return score_fit(in_, std::move(effects), params, free_params, make, make);
}

EffectFit ResidualLoop::base_on_all(const EffectFit& searched) const {
  const auto t0 = std::chrono::steady_clock::now();
  ParamSet base = searched.fit.params;
  if (o_.fit_base) {
    o_.progress("base model refit on every calibration sample", 1.0);
    FitOptions fo = fit_options();
    fo.stages = {"joint"};
    fo.function_tolerance = o_.refit_on_all_tolerance;
    const CalibrationResult r = fit_model(in_.model_id, in_.sensor, in_.calibration, base, fo);
    throw_if_cancelled(r, o_.progress);
    base = r.params;
  }
  EffectFit ef = scored_on_all(in_.model_id, {}, base, searched.fit.free_params);
  ef.time_s = searched.time_s + seconds_since(t0);
  return ef;
}

// Step 1: the base model fitted (its stages, then jointly: fit.hpp) or as given.
EffectFit ResidualLoop::fit_base() const {
  const auto t0 = std::chrono::steady_clock::now();
  ParamSet base = in_.base_params;
  if (o_.fit_base) {
    o_.progress("base model fit", 0.0);
    const CalibrationResult r =
        fit_model(in_.model_id, in_.sensor, search_in().calibration, in_.base_params, fit_options());
    throw_if_cancelled(r, o_.progress);
    base = r.params;
  }
  EffectFit ef = scored(in_.model_id, {}, base, o_.fit_base ? joint_stage(in_.model_id, false).params.size() : 0);
  ef.time_s = seconds_since(t0);
  return ef;
}

// Step 2, a variant alone: its own parameters (those its joint stage adds to the base's) fitted on the search's
// subset from their defaults, the base's at their fitted values.
EffectFit ResidualLoop::fit_variant_alone(const std::string& v, const EffectFit& base) const {
  o_.progress("model form " + v + " alone", 0.0);
  const auto t0 = std::chrono::steady_clock::now();
  ParamSet start = default_params(v);
  copy_shared(base.fit.params, &start);
  const std::vector<std::string> base_joint = joint_stage(in_.model_id, false).params;
  std::vector<std::string> own = joint_stage(v, false).params;
  std::erase_if(own, [&](const std::string& n) { return std::count(base_joint.begin(), base_joint.end(), n) != 0; });
  ParamSet fitted = start;
  if (!own.empty()) {
    const FitStage stage{"alone", own, joint_stage(v, false).motions, false, {}};
    const CalibrationResult r =
        run_fit_stages(v, spec_fit_factory(v, in_.sensor), {stage}, search_cal_, start, fit_options());
    throw_if_cancelled(r, o_.progress);
    fitted = r.params;
  }
  EffectFit ef = scored(v, {}, fitted, base.fit.free_params + own.size());
  ef.time_s = seconds_since(t0);
  return ef;
}

// Step 2, a variant refitted: fitted like the base (its stages, then jointly) on the search's subset, from the
// fitted base's values and the variant's own defaults, with `hold` kept after their first stage. Not jointly from
// its alone fit: on the FE twin slice that start leaves the contact variant in a shallower valley, where a tracker
// bias then passes the held-out rule on top of it.
EffectFit ResidualLoop::fit_variant(const std::string& v, const EffectFit& base,
                                    const std::vector<std::string>& hold) const {
  o_.progress("model form " + v + (hold.empty() ? "" : ", held after their stage: " + effect_set_key(hold)), 0.0);
  const auto t0 = std::chrono::steady_clock::now();
  ParamSet start = default_params(v);
  copy_shared(base.fit.params, &start);
  FitOptions fo = fit_options();
  fo.hold = hold;
  const CalibrationResult r = fit_model(v, in_.sensor, search_cal_, start, fo);
  throw_if_cancelled(r, o_.progress);
  EffectFit ef = scored(v, {}, r.params, joint_stage(v, false).params.size());
  ef.time_s = seconds_since(t0);
  return ef;
}

// Step 2: the variants as the effect rounds treat a candidate. Each is fitted alone (fit_variant_alone); those
// that gain at least ResidualOptions::screen_min_pct on validation, best alone first, up to
// joint_refits_per_round, are refitted (fit_variant) and scored against the base by the selection rule; the others
// are reported as screened. The selected one is refitted with model_form_hold held after their first stage (the
// dilation kernel as the presses fit it), kept when held-out data prefer it.
ModelFormRound ResidualLoop::model_form_round(const EffectFit& base) const {
  ModelFormRound round;
  if (!o_.model_forms || !o_.fit_base) return round;
  const std::vector<std::string> variants = model_form_variants(in_.model_id);
  const double base_rmse = validation_rmse(base.fit.validation);
  std::vector<EffectFit> alone;
  std::vector<double> alone_rmse, gain_pct;
  std::vector<bool> in_ranking;
  for (const std::string& v : variants) {
    alone.push_back(fit_variant_alone(v, base));
    alone_rmse.push_back(validation_rmse(alone.back().fit.validation));
    gain_pct.push_back(100.0 * (base_rmse - alone_rmse.back()) / base_rmse);
    in_ranking.push_back(gain_pct.back() >= o_.screen_min_pct);
  }
  const std::vector<std::size_t> rank = joint_refit_ranks(alone_rmse, in_ranking);
  const auto ranked = static_cast<std::size_t>(std::count(in_ranking.begin(), in_ranking.end(), true));
  double best_rmse_px = 0;
  for (std::size_t i = 0; i < variants.size(); ++i) {
    const std::string& v = variants[i];
    EffectFit ef = alone[i];
    if (rank[i] >= 1 && rank[i] <= o_.joint_refits_per_round) {
      ef = fit_variant(v, base, {});
      ef.time_s += alone[i].time_s;
    } else {
      ef.fit.veto = screen_note(gain_pct[i], o_.screen_min_pct, rank[i], ranked, o_.joint_refits_per_round, "variants");
    }
    CandidateScore sc = score_candidate(base.fit, ef.fit, o_.selection);
    sc.candidate = v;
    if (sc.accepted && (round.selected.empty() || sc.rmse_px < best_rmse_px))
      round.selected = v, best_rmse_px = sc.rmse_px;
    round.scores.push_back(std::move(sc));
    round.fits[v] = std::move(ef);
  }
  const std::vector<std::string> hold = model_form_hold(in_.model_id);
  if (round.selected.empty() || hold.empty()) return round;
  EffectFit ef = fit_variant(round.selected, base, hold);
  CandidateScore sc = score_candidate(base.fit, ef.fit, o_.selection);
  sc.candidate = round.selected;
  if (!sc.accepted || sc.rmse_px >= best_rmse_px) return round;
  round.held = hold;
  round.joint_rmse_px = best_rmse_px;
  const auto it = std::find_if(round.scores.begin(), round.scores.end(),
                               [&](const auto& c) { return c.candidate == round.selected; });
  if (it != round.scores.end()) *it = std::move(sc);  // one score per variant: moved once
  round.fits[round.selected] = std::move(ef);
  return round;
}

// Step 3: the catalogued effects on top of the form, greedily (residual_select.hpp, effect_search.hpp).
// A selected model-form variant was fitted on the search's subset; the base on every sample.
EffectRounds ResidualLoop::effect_rounds(const std::string& form, const EffectFit& form_fit) const {
  const bool form_on_subset = form != in_.model_id && search_cal_.size() < search_in().calibration.size();
  EffectSearch search(search_in(), o_, fit_options(), form, form_fit, candidates_,
                      {search_cal_, form_on_subset, searched_on_part() ? &in_ : nullptr});
  EffectRounds rounds;
  rounds.form = form;
  rounds.selection = select_effects(
      candidates_, [&](const std::vector<std::string>& ids) { return search.fit_and_score(ids); }, o_.selection);
  rounds.final_refit = search.final_refit(rounds.selection.selected, &rounds.final_refit_why);
  rounds.fits = search.take_fits();
  return rounds;
}

// Step 4: the form plus the selected effects. Every selected set was fitted jointly with the form in the
// rounds (a set is accepted only after its joint refit, or when the form is not fitted), so its fit is the
// final model's; after a pose effect the rounds held the form's state and the pose, and the final refit
// (step 3's last act) freed them.
FinalModel ResidualLoop::final_fit(const EffectRounds& rounds) const {
  if (rounds.final_refit) return {ModelSpec{rounds.form, rounds.selection.selected}.id(), *rounds.final_refit};
  return {ModelSpec{rounds.form, rounds.selection.selected}.id(),
          rounds.fits.at(effect_set_key(rounds.selection.selected))};
}

// Step 5: the residual structure of a model over both splits (at most ResidualOptions::structure_samples).
ResidualStructure ResidualLoop::score(const std::string& model_id, const EffectFit& fit) const {
  return analyse_residual(model_id, fit.fit.params, in_.sensor, structure_samples_, o_.bins);
}

// Step 5 too: the responses of the measured field and of the model to the known inputs. The response
// surface's degree drops where the calibration split has too few frames for a cubic's 84 terms (3 frames a term).
std::optional<InputResponseAnalysis> ResidualLoop::input_response(const std::string& model_id,
                                                                  const EffectFit& fit) const {
  // A description of the responses, not a score: the search set's samples (all of them on a smaller set).
  const auto cal = scored_input_frames(model_id, fit.fit.params, in_.sensor, search_in().calibration);
  const auto val = scored_input_frames(model_id, fit.fit.params, in_.sensor, search_in().validation);
  constexpr std::size_t kFramesPerTerm = 3;
  const int degree = cal.size() >= 84 * kFramesPerTerm ? 3 : cal.size() >= 28 * kFramesPerTerm ? 2 : 1;
  if (cal.size() < 7 * kFramesPerTerm || val.empty()) return std::nullopt;
  return analyse_input_response(cal, val, degree);
}

// The answer's free parameters: its form's joint ones (when the base is fitted) and its effects'.
std::vector<std::string> ResidualLoop::answer_free_params(const ResidualReport& rep) const {
  std::vector<std::string> free;
  if (o_.fit_base) free = joint_stage(rep.effects.form, false).params;
  for (const auto& id : rep.effects.selection.selected) {
    const auto names = effect_fit_params(rep.after.fit.params, id);
    free.insert(free.end(), names.begin(), names.end());
  }
  return free;
}

ResidualReport ResidualLoop::run() const {
  const auto t0 = std::chrono::steady_clock::now();
  ResidualReport rep;
  rep.dataset = in_.dataset;
  rep.model_id = in_.model_id;
  rep.fit_base = o_.fit_base;
  rep.search_samples = search_cal_.size();
  rep.calibration_samples = in_.calibration.size();
  rep.structure_samples = structure_samples_.size();
  rep.all_samples = in_.calibration.size() + in_.validation.size();
  rep.search_set_samples = search_in().calibration.size() + search_in().validation.size();
  rep.sensor = in_.sensor;
  rep.before = fit_base();
  rep.model_form = model_form_round(rep.before);
  const bool form_selected = !rep.model_form.selected.empty();
  const std::string form = form_selected ? rep.model_form.selected : in_.model_id;
  rep.effects = effect_rounds(form, form_selected ? rep.model_form.fits.at(form) : rep.before);
  FinalModel final_model = final_fit(rep.effects);
  rep.after_model = final_model.model_id;
  rep.after = std::move(final_model.fit);
  if (searched_on_part()) {
    // The search's scores are the search set's; what is reported of the base and the answer is every sample's.
    rep.before = base_on_all(rep.before);
    if (!rep.effects.final_refit) {
      EffectFit all =
          scored_on_all(rep.after_model, rep.after.effects, rep.after.fit.params, rep.after.fit.free_params);
      all.fit.fingerprint = rep.after.fit.fingerprint;
      all.time_s = rep.after.time_s;
      rep.after = std::move(all);
    }
  }
  o_.progress("evidence of the answer's effects", 1.0);
  rep.evidence = answer_evidence(in_.sensor, rep.effects.form, rep.effects.selection.selected, rep.after.fit.params,
                                 in_.calibration, in_.validation);
  rep.answer_at_bound = params_at_bounds(rep.after.fit.params, answer_free_params(rep));
  o_.progress("residual structure", 1.0);
  rep.structure_before = score(in_.model_id, rep.before);
  rep.structure_after = score(rep.after_model, rep.after);
  rep.response_before = input_response(in_.model_id, rep.before);
  if (rep.after_model != in_.model_id) rep.response_after = input_response(rep.after_model, rep.after);
  rep.time_s = seconds_since(t0);
  return rep;
}

ResidualReport run_residual_loop(const ResidualInputs& in, const ResidualOptions& options) {
  return ResidualLoop(in, options).run();
}

nlohmann::ordered_json effect_params_json(const ParamSet& params, const std::string& effect_id) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  const std::string prefix = effect_id + kEffectParamSeparator;
  for (std::size_t i = 0; i < params.size(); ++i) {
    const std::string& n = params.specs()[i].name;
    if (n.rfind(prefix, 0) == 0) j[n.substr(prefix.size())] = params[i];
  }
  return j;
}

nlohmann::ordered_json final_model_params_json(const ResidualReport& r) {
  nlohmann::ordered_json table = nlohmann::ordered_json::object();
  const ParamSet& p = r.after.fit.params;
  for (std::size_t i = 0; i < p.size(); ++i) table[p.specs()[i].name] = p[i];
  nlohmann::ordered_json j;
  j[r.after_model] = table;
  return j;
}

}  // namespace sb
