// Step 3 of the residual loop: effects on top of the fitted form (effect_search.hpp).
#include "core/loop/effect_search.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <iterator>
#include <limits>
#include <utility>

#include "core/base/elapsed.hpp"
#include "core/base/format.hpp"
#include "core/calibration/fit.hpp"
#include "core/data/tsd.hpp"
#include "core/effects/effects.hpp"
#include "core/effects/model_spec.hpp"
#include "core/loop/fingerprints.hpp"

namespace sb {

namespace {

// Advances the odometer `at` over the grid `axes` (last axis fastest); false after the last point.
bool next_grid_point(const std::vector<std::vector<double>>& axes, std::vector<std::size_t>* at) {
  for (std::size_t i = at->size(); i-- > 0;) {
    if (++(*at)[i] < axes[i].size()) return true;
    (*at)[i] = 0;
  }
  return false;
}

std::vector<std::string> without(std::vector<std::string> names, const std::vector<std::string>& held) {
  std::erase_if(names, [&](const std::string& n) { return std::find(held.begin(), held.end(), n) != held.end(); });
  return names;
}

// The free parameters of `effect_id` that sit at a bound of their range ("name = value"), except a bound
// that is the parameter's own "no effect" default (subsurface depth 0, edge strength 0): reaching that
// means the effect switched itself off, not that it was pushed past physics.
std::string params_at_bound(const ParamSet& params, const std::string& effect_id,
                            const std::vector<std::string>& held) {
  std::string out;
  for (const auto& b : params_at_bounds(params, without(effect_fit_params(params, effect_id), held)))
    if (!b.is_default) out += (out.empty() ? "" : ", ") + b.name + " = " + format_number(b.value, "%.4g");
  return out;
}

// A fingerprint that model form can mimic must agree with the whole-field fit: a fitted value outside its
// band is a verdict like a bound (the whole field wants something else than the evidence).
std::string outside_band(const ParamSet& fitted, const std::string& candidate,
                         const std::optional<FingerprintCheck>& fp) {
  std::string out;
  if (!fp || !fp->consistent) return out;
  for (const auto& b : fp->band) {
    const std::string name = candidate + kEffectParamSeparator + b.name;
    const double v = fitted.get(name);
    if (v >= b.low && v <= b.high) continue;
    out += (out.empty() ? "" : ", ") + name + " = " + format_number(v, "%.4g") + " outside its fingerprint's band [" +
           format_number(b.low, "%.4g") + ", " + format_number(b.high, "%.4g") + "]";
  }
  return out;
}

}  // namespace

EffectFit score_fit(const ResidualInputs& in, std::vector<std::string> effects, const ParamSet& params,
                    std::size_t free_params, const SampleModelFactory& make_cal, const SampleModelFactory& make_val) {
  EffectFit ef;
  ef.effects = std::move(effects);
  ef.fit.params = params;
  ef.fit.free_params = free_params;
  const SplitScores cal = score_samples(make_cal, params, *in.sensor, in.calibration);
  for (std::size_t i = 0; i < cal.sse.size(); ++i) {
    ef.fit.calibration_sse_px2 += cal.sse[i];
    ef.fit.calibration_count += 2 * cal.count[i];
  }
  SplitScores val = score_samples(make_val, params, *in.sensor, in.validation);
  ef.fit.held_sse_px2 = val.held_sse;
  ef.fit.held_signal_px2 = val.held_signal;
  ef.fit.held_count = val.held_count;
  ef.fit.validation.sq_err_px2 = std::move(val.sse);
  ef.fit.validation.count = std::move(val.count);
  ef.validation = std::move(val.metrics);
  return ef;
}

std::vector<std::size_t> joint_refit_ranks(const std::vector<double>& alone_rmse_px,
                                           const std::vector<bool>& in_ranking) {
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < alone_rmse_px.size(); ++i)
    if (in_ranking.at(i)) order.push_back(i);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return alone_rmse_px[a] < alone_rmse_px[b]; });
  std::vector<std::size_t> rank(alone_rmse_px.size(), 0);
  for (std::size_t r = 0; r < order.size(); ++r) rank[order[r]] = r + 1;
  return rank;
}

std::string screen_note(double gain_pct, double min_pct, std::size_t rank, std::size_t ranked, std::size_t keep,
                        const std::string& what) {
  const std::string gain = "screened: alone over the fitted base it gains " + format_number(gain_pct, "%.2f") + "%";
  if (rank == 0) return gain + " (< " + format_number(min_pct, "%.2f") + "%), no joint refit";
  return gain + ", " + std::to_string(rank) + " of " + std::to_string(ranked) + " promising " + what + "; only the " +
         std::to_string(keep) + " best alone get the joint refit";
}

EffectSearch::EffectSearch(const ResidualInputs& in, const ResidualOptions& o, const FitOptions& fo, std::string form,
                           const EffectFit& form_fit, std::vector<std::string> candidates, SearchSubset subset)
    : in_(in), o_(o), fo_(fo), form_(std::move(form)), candidates_(std::move(candidates)), subset_(subset) {
  if (o.fit_base) form_free_ = joint_stage(form_, false).params;
  fits_[""] = form_fit;
  fp_cal_ = fingerprint_samples(*in.sensor, in.calibration);
  fp_val_ = fingerprint_samples(*in.sensor, in.validation);
}

void EffectSearch::progress(const std::string& what) const {
  const double total = static_cast<double>(candidates_.size() * o_.selection.max_effects + 1);
  o_.progress(what, (static_cast<double>(fits_.size()) + 0.5 * static_cast<double>(alone_.size())) / total);
}

EffectSearch::Start EffectSearch::start_of(const std::vector<std::string>& ids) const {
  Start s{model_spec_params(ModelSpec{form_, ids}.id()), {}};
  copy_shared(fits_.at("").fit.params, &s.params);
  const std::vector<std::string> prefix(ids.begin(), ids.end() - 1);
  if (auto it = fits_.find(effect_set_key(prefix)); it != fits_.end()) {
    copy_shared(it->second.fit.params, &s.params);
    s.warm = prefix;
  }
  return s;
}

// The form's field under the set's pose effects (they change what the form sees; the others act on its field).
const EffectSearch::Recording& EffectSearch::recording(const std::vector<std::string>& ids) {
  const std::string key = effect_set_key(ids);
  if (auto it = recordings_.find(key); it != recordings_.end()) return it->second;
  // A round replays the recording of its warm start only, and no factory outlives the fit or score that made it:
  // one recording is kept at a time (each is the form's field on every sample of both splits).
  recordings_.clear();
  const ParamSet& p = fits_.at(key).fit.params;
  std::vector<std::string> pose_effects;
  std::copy_if(ids.begin(), ids.end(), std::back_inserter(pose_effects),
               [](const std::string& id) { return any_acts_on_pose({id}); });
  const std::string recorded = ModelSpec{form_, pose_effects}.id();
  Recording r{record_field(recorded, p, in_.sensor, in_.calibration),
              record_field(recorded, p, in_.sensor, in_.validation),
              subsampled() ? record_field(recorded, p, in_.sensor, subset_.calibration) : std::vector<RecordedField>{}};
  return recordings_.emplace(key, std::move(r)).first->second;  // map nodes are stable: factories keep pointers
}

SampleModelFactory EffectSearch::replay(const std::vector<std::string>& ids, const std::string& warm_key,
                                        const std::vector<RecordedField>& field) const {
  return replay_factory(form_, ids, fits_.at(warm_key).fit.params, &field, in_.sensor);
}

std::optional<FingerprintCheck> EffectSearch::fingerprint_of(const std::string& candidate,
                                                             const std::vector<std::string>& warm) {
  progress("fingerprint " + candidate);
  if (!fingerprint_needs_model(candidate, *in_.sensor))
    return fingerprint_check(candidate, *in_.sensor, fp_cal_, fp_val_);
  const std::string key = effect_set_key(warm);
  const Recording& rec = recording(warm);
  const ParamSet& p = fits_.at(key).fit.params;
  const ModelFieldScope cal(&fp_cal_, replay(warm, key, rec.cal), p, in_.calibration);
  const ModelFieldScope val(&fp_val_, replay(warm, key, rec.val), p, in_.validation);
  return fingerprint_check(candidate, *in_.sensor, fp_cal_, fp_val_);
}

std::vector<std::string> EffectSearch::hold_fingerprint(const std::string& candidate, const FingerprintCheck& fp,
                                                        ParamSet* start) {
  std::vector<std::string> held;
  for (const auto& [name, value] : fp.held) {
    const std::string full = (candidate + kEffectParamSeparator).append(name);
    const ParamSpec& sp = start->specs()[static_cast<std::size_t>(start->index_of(full))];
    start->set(full, std::clamp(value, sp.min, sp.max));
    held.push_back(full);
  }
  // Later rounds hold the band's parameters too, at this fit's values.
  auto& later = held_by_effect_[candidate];
  later = held;
  for (const auto& b : fp.band) later.push_back(candidate + kEffectParamSeparator + b.name);
  return held;
}

std::vector<std::string> EffectSearch::held_of(const std::string& effect, const std::string& candidate,
                                               const std::vector<std::string>& held_now) const {
  if (effect == candidate) return held_now;
  const auto it = held_by_effect_.find(effect);
  return it == held_by_effect_.end() ? std::vector<std::string>{} : it->second;
}

// A pose effect's cost is not convex in its parameters: the tool frame's pivot and zero trade (a deeper zero and
// a pivot nearer the apex both deepen a tilted press), and apart each makes the fitted form worse, so from the
// defaults Levenberg-Marquardt stops in the nearest valley (the TacTip: a pivot 1.7 mm below the apex; the
// data want ~20 mm with a 1 mm zero). The fit starts from the best point of a coarse grid over the stages'
// ranges instead: kGridPoints per parameter (cell centres) and the start, up to two parameters.
ParamSet EffectSearch::grid_start(const std::string& model_id, const std::vector<FitStage>& stages,
                                  const ParamSet& start) const {
  constexpr int kGridPoints = 4;
  constexpr std::size_t kMaxGridParams = 2;
  std::vector<std::string> names;
  for (const auto& st : stages) names.insert(names.end(), st.params.begin(), st.params.end());
  if (names.empty() || names.size() > kMaxGridParams) return start;
  std::vector<std::vector<double>> axes;
  for (const auto& name : names) {
    const ParamSpec& sp = start.specs()[static_cast<std::size_t>(start.index_of(name))];
    std::vector<double> axis{start.get(name)};
    for (int k = 0; k < kGridPoints; ++k) axis.push_back(sp.min + (sp.max - sp.min) * (k + 0.5) / kGridPoints);
    axes.push_back(std::move(axis));
  }
  progress("grid start " + model_id);
  ParamSet best = start, trial = start;
  double best_rmse = std::numeric_limits<double>::infinity();
  std::vector<std::size_t> at(names.size(), 0);
  do {
    if (fo_.cancel != nullptr && fo_.cancel->load()) break;
    for (std::size_t i = 0; i < names.size(); ++i) trial.set(names[i], axes[i][at[i]]);
    if (const double rmse = fit_rmse_px(model_id, in_.sensor, subset_.calibration, trial); rmse < best_rmse) {
      best_rmse = rmse;
      best = trial;
    }
  } while (next_grid_point(axes, &at));
  return best;
}

EffectFit EffectSearch::fit_alone(const std::vector<std::string>& ids, const Start& start,
                                  const std::vector<FitStage>& stages) {
  const std::string key = effect_set_key(ids), warm_key = effect_set_key(start.warm);
  // A new pose effect changes what the form sees: its fit reruns the form; the others replay its field.
  std::vector<std::string> added;
  std::copy_if(ids.begin(), ids.end(), std::back_inserter(added), [&](const std::string& id) {
    return std::find(start.warm.begin(), start.warm.end(), id) == start.warm.end();
  });
  // Every alone fit sees the search's subset; its scores see every sample.
  SampleModelFactory make_cal, make_val, make_fit;
  if (any_acts_on_pose(added)) {
    make_cal = make_val = make_fit = spec_model_factory(ModelSpec{form_, ids}.id(), in_.sensor);
  } else {
    const Recording& rec = recording(start.warm);
    make_cal = replay(ids, warm_key, rec.cal);
    make_val = replay(ids, warm_key, rec.val);
    make_fit = subsampled() ? replay(ids, warm_key, rec.subset) : make_cal;
  }
  ParamSet from = start.params;
  if (any_acts_on_pose(added) && !stages.empty()) from = grid_start(ModelSpec{form_, ids}.id(), stages, from);
  CalibrationResult r{form_ + "+" + key, from, {}, false, 0};
  if (!stages.empty())
    r = run_fit_stages_per_sample(form_ + "+" + key, make_fit, stages, subset_.calibration, from, fo_);
  throw_if_cancelled(r, o_.progress);
  std::size_t free_count = 0;
  for (const auto& st : stages) free_count += st.params.size();
  return score_fit(in_, ids, r.params, free_count + fits_.at(warm_key).fit.free_params, make_cal, make_val);
}

// The joint refit (every run reruns the form) only for an effect that alone, over the reference's recorded
// field, already buys part of the acceptance margin on validation, explains the held drift, or whose
// fingerprint was found. Joint refits may let the form's parameters lean on the effect, but an effect the
// data hold shows on the form as fitted.
bool EffectSearch::promising(const EffectFit& alone, const std::string& warm_key,
                             const std::optional<FingerprintCheck>& fp, std::string* screen_note,
                             bool* by_evidence) const {
  const FitResult& ref = fits_.at(warm_key).fit;
  const double ref_rmse = validation_rmse(ref.validation);
  const double alone_pct = 100.0 * (ref_rmse - validation_rmse(alone.fit.validation)) / ref_rmse;
  const double drift_pct = fingerprint_explained_pct(ref, alone.fit, o_.selection);
  const bool drift = std::isfinite(drift_pct) && drift_pct >= o_.selection.min_fingerprint_pct;
  *by_evidence = (fp && fp->consistent) || (!fp && drift);
  if (fp) return fp->consistent;
  if (alone_pct >= o_.screen_min_pct || drift) return true;
  *screen_note = sb::screen_note(alone_pct, o_.screen_min_pct, 0, 0, 0, "candidates");
  return false;
}

EffectFit EffectSearch::joint_refit(const std::vector<std::string>& ids, const std::vector<std::string>& joint,
                                    const ParamSet& from, const std::vector<FitSample>& fit_on,
                                    const ResidualInputs& score_on, const FitOptions& fo) {
  const std::string model = ModelSpec{form_, ids}.id();
  const std::vector<FitStage> stage{{"joint", joint, tsd_motions(), false, {}}};
  const CalibrationResult r = run_fit_stages(model, spec_fit_factory(model, in_.sensor), stage, fit_on, from, fo);
  throw_if_cancelled(r, o_.progress);
  const SampleModelFactory full = spec_model_factory(model, in_.sensor);
  return score_fit(score_on, ids, r.params, joint.size(), full, full);
}

// A bound or a band verdict on the candidate's fitted parameters (docs/effects.md, "Model-form symptoms").
void EffectSearch::add_verdict(const std::string& candidate, const std::vector<std::string>& held_now,
                               const std::optional<FingerprintCheck>& fp, EffectFit* ef) const {
  if (!ef->fit.veto.empty()) return;
  const std::string bound = params_at_bound(ef->fit.params, candidate, held_of(candidate, candidate, held_now));
  const std::string band = outside_band(ef->fit.params, candidate, fp);
  if (bound.empty() && band.empty()) return;
  ef->fit.veto = "model-form symptom: " + (bound.empty() ? band + ": the whole field disagrees with the evidence"
                                                         : bound + " at a bound of its physical range");
  ef->fit.model_form_symptom = true;
}

std::vector<std::string> EffectSearch::shaping_held(const std::vector<std::string>& warm) const {
  if (!any_acts_on_pose(warm)) return {};
  const ParamSet form_table = model_spec_params(form_);
  std::vector<std::string> held;
  for (const auto& name : form_free_)
    if (!form_table.specs()[static_cast<std::size_t>(form_table.index_of(name))].field_only) held.push_back(name);
  const ParamSet& warm_params = fits_.at(effect_set_key(warm)).fit.params;
  for (const auto& id : warm)
    if (any_acts_on_pose({id})) {
      const auto names = effect_fit_params(warm_params, id);
      held.insert(held.end(), names.begin(), names.end());
    }
  return held;
}

std::optional<EffectFit> EffectSearch::final_refit(const std::vector<std::string>& selected, std::string* why) {
  const std::vector<std::string> warm(selected.begin(), selected.end() - (selected.empty() ? 0 : 1));
  const bool held = !selected.empty() && !shaping_held(warm).empty();
  // With the form fitted, every selected set was refitted jointly (on the subset); without, a pose effect was.
  const bool searched_on_part = subset_.all != nullptr;
  const bool on_subset = searched_on_part ||
                         (subsampled() && (subset_.form_fitted_on_it ||
                                           (!selected.empty() && (!form_free_.empty() || any_acts_on_pose(selected)))));
  if (!held && !on_subset) return std::nullopt;
  const std::size_t n = subset_.calibration.size(), all = whole().calibration.size();
  *why = held ? "the rounds held the form's state and the pose effect's parameters after its round" : "";
  if (on_subset)
    *why += (why->empty() ? "" : "; ") + std::string("the search fitted it on ") + std::to_string(n) + " of the " +
            std::to_string(all) + " calibration samples";
  const auto t0 = std::chrono::steady_clock::now();
  const EffectFit& rounds_fit = fits_.at(effect_set_key(selected));
  std::vector<std::string> joint = form_free_;
  for (const auto& id : selected) {
    const auto free = without(effect_fit_params(rounds_fit.fit.params, id), held_of(id, "", {}));
    joint.insert(joint.end(), free.begin(), free.end());
  }
  if (joint.empty()) return std::nullopt;
  progress("final joint refit " + ModelSpec{form_, selected}.id());
  FitOptions fo = fo_;
  if (subset_.all != nullptr) fo.function_tolerance = o_.refit_on_all_tolerance;  // from the search's optimum
  EffectFit ef = joint_refit(selected, joint, rounds_fit.fit.params, whole().calibration, whole(), fo);
  ef.fit.fingerprint = rounds_fit.fit.fingerprint;
  ef.time_s = seconds_since(t0);
  return ef;
}

EffectSearch::Alone EffectSearch::fit_alone_phase(const std::vector<std::string>& ids) {
  const auto t0 = std::chrono::steady_clock::now();
  Alone a;
  a.start = start_of(ids);
  const std::string& candidate = ids.back();
  // The candidate's fingerprint, against the reference (the warm start's model). Found: its parameters are
  // held at the estimate (evidence beyond model form), or fitted as without a fingerprint and checked against
  // its band (evidence model form can mimic: it may add a verdict, never lift one). Not found: fitted alone.
  if (has_fingerprint(candidate) && a.start.warm.size() + 1 == ids.size()) {
    a.fp = fingerprint_of(candidate, a.start.warm);
    if (a.fp && a.fp->consistent) a.held_now = hold_fingerprint(candidate, *a.fp, &a.start.params);
  }
  std::vector<FitStage> stages;
  a.shaping = shaping_held(a.start.warm);
  a.joint = without(form_free_, a.shaping);
  for (const auto& id : ids) {
    const auto free =
        without(without(effect_fit_params(a.start.params, id), held_of(id, candidate, a.held_now)), a.shaping);
    a.joint.insert(a.joint.end(), free.begin(), free.end());
    if (std::find(a.start.warm.begin(), a.start.warm.end(), id) == a.start.warm.end() && !free.empty())
      stages.push_back({"effect:" + id, free, tsd_motions(), false, {}});
  }
  progress("fit " + form_ + "+" + effect_set_key(ids));
  a.fit = fit_alone(ids, a.start, stages);
  const std::string warm_key = effect_set_key(a.start.warm);
  a.free_count = a.fit.fit.free_params - fits_.at(warm_key).fit.free_params;
  a.promising = promising(a.fit, warm_key, a.fp, &a.screen_note, &a.by_evidence);
  a.time_s = seconds_since(t0);
  return a;
}

void EffectSearch::prepare_round(const std::vector<std::string>& selected) {
  std::vector<std::string> keys;
  for (const auto& c : candidates_) {
    if (std::find(selected.begin(), selected.end(), c) != selected.end()) continue;
    std::vector<std::string> ids = selected;
    ids.push_back(c);
    const std::string key = effect_set_key(ids);
    if (fits_.count(key) != 0 || alone_.count(key) != 0) continue;
    alone_.emplace(key, fit_alone_phase(ids));
    keys.push_back(key);
  }
  // A joint refit reruns the form on every run (minutes on a real set): only the best few alone get one.
  std::vector<double> rmse;
  std::vector<bool> in_ranking;
  for (const auto& k : keys) {
    const Alone& a = alone_.at(k);
    rmse.push_back(validation_rmse(a.fit.fit.validation));
    in_ranking.push_back(a.promising && !a.by_evidence && a.joint.size() > a.free_count);
  }
  const std::vector<std::size_t> rank = joint_refit_ranks(rmse, in_ranking);
  const auto ranked = static_cast<std::size_t>(std::count(in_ranking.begin(), in_ranking.end(), true));
  const std::size_t keep = o_.joint_refits_per_round;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    if (rank[i] <= keep) continue;
    Alone& a = alone_.at(keys[i]);
    const double ref = validation_rmse(fits_.at(effect_set_key(a.start.warm)).fit.validation);
    a.promising = false;
    a.screen_note = screen_note(100.0 * (ref - rmse[i]) / ref, o_.screen_min_pct, rank[i], ranked, keep, "candidates");
  }
}

EffectFit EffectSearch::finish(const std::vector<std::string>& ids, Alone a) {
  const auto t0 = std::chrono::steady_clock::now();
  EffectFit ef = std::move(a.fit);
  if (a.promising && a.joint.size() > a.free_count) {
    progress("joint refit " + form_ + "+" + effect_set_key(ids));
    ef = joint_refit(ids, a.joint, ef.fit.params, subset_.calibration, in_, fo_);
    ef.fit.free_params += a.shaping.size();  // fitted all the same, in an earlier round
  } else if (a.joint.size() > a.free_count && !a.fp)
    ef.fit.veto = a.screen_note;
  add_verdict(ids.back(), a.held_now, a.fp, &ef);
  ef.fit.fingerprint = a.fp;
  ef.time_s = a.time_s + seconds_since(t0);
  return ef;
}

FitResult EffectSearch::fit_and_score(const std::vector<std::string>& ids) {
  const std::string key = effect_set_key(ids);
  if (auto it = fits_.find(key); it != fits_.end()) return it->second.fit;
  if (alone_.count(key) == 0) prepare_round({ids.begin(), ids.end() - 1});
  auto node = alone_.extract(key);
  return (fits_[key] = finish(ids, std::move(node.mapped()))).fit;
}

}  // namespace sb
