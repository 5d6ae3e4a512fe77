#pragma once
// Step 3 of the residual loop (residual.hpp): the catalogued effects on top of a fitted form, searched
// greedily by select_effects. EffectSearch owns what the search accumulates: each effect set's fit, the
// form's recorded field at the round's warm start (an effect-only fit replays it instead of rerunning the
// form), and the effect parameters a fingerprint settled. See docs/effects.md, "The loop, step by step".
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/loop/loop_samples.hpp"
#include "core/loop/residual.hpp"

namespace sb {

// A fitted model's scores on both splits: calibration SSE for the BIC, validation errors per sample, the
// held-drift sums and the per-motion metrics.
EffectFit score_fit(const ResidualInputs& in, std::vector<std::string> effects, const ParamSet& params,
                    std::size_t free_params, const SampleModelFactory& make_cal, const SampleModelFactory& make_val);

// A round's candidates ranked for the joint refit: rank r (1-based) by ascending alone validation RMSE among
// those `in_ranking` (promising, refitted only by rank), stable in candidate order; 0 for the others.
std::vector<std::size_t> joint_refit_ranks(const std::vector<double>& alone_rmse_px,
                                           const std::vector<bool>& in_ranking);

// The calibration samples the search's costly fits see (ResidualOptions::search_samples), and whether the form's
// own fit saw only them (a model-form variant's does; the base's saw every sample of the search's inputs).
// `all`: the whole set the answer is refitted and scored on when the search's inputs are its search set
// (ResidualOptions::search_set); nullptr when they are the whole set.
struct SearchSubset {
  const std::vector<FitSample>& calibration;
  bool form_fitted_on_it = false;
  const ResidualInputs* all = nullptr;
};

// Why a candidate (an effect, or a model-form variant) got no joint refit: it gains `gain_pct` alone over the
// fitted base; `rank` 0 when below `min_pct`, else its joint_refit_ranks rank of `ranked`, past the best `keep`.
std::string screen_note(double gain_pct, double min_pct, std::size_t rank, std::size_t ranked, std::size_t keep,
                        const std::string& what);

class EffectSearch {
 public:
  // `form_fit` is the form as fitted (the search's reference, key ""); `fo` the fits' options.
  // `candidates` are select_effects' candidates: a round's sets are the selection so far plus each of the rest.
  // Every fit of the search (a candidate alone, over the recorded field or rerunning the form for a pose effect,
  // a pose effect's grid start, a joint refit) sees `subset`'s samples; every score uses all of both splits.
  EffectSearch(const ResidualInputs& in, const ResidualOptions& o, const FitOptions& fo, std::string form,
               const EffectFit& form_fit, std::vector<std::string> candidates, SearchSubset subset);

  // select_effects' FitAndScore: the set `ids` fitted on top of the form and scored (cached by set).
  FitResult fit_and_score(const std::vector<std::string>& ids);
  std::map<std::string, EffectFit> take_fits() { return std::move(fits_); }
  // The selected set fitted once more on every calibration sample (of SearchSubset::all when given) with every
  // parameter free (the form's and all effects' but those a fingerprint settled) when its rounds held what shapes
  // the form's field (shaping_held) or fitted it on a subset, and scored there; `why` says which. nullopt
  // otherwise: the set's own fit already is the answer.
  std::optional<EffectFit> final_refit(const std::vector<std::string>& selected, std::string* why);

 private:
  // The form's field on every sample of both splits (scores replay these), and on the search's subset when it is
  // smaller than the calibration split (alone fits replay that: fitting a candidate is screening, scoring is not).
  struct Recording {
    std::vector<RecordedField> cal, val, subset;
  };
  // The start of a set's fit and the fitted set it is warm-started from (the set without its last effect).
  struct Start {
    ParamSet params;
    std::vector<std::string> warm;
  };
  // A set's first phase: its candidate fitted alone (over the reference's recorded field, or rerunning the form
  // for a pose effect), and what its joint refit would free. The round ranks these before any joint refit.
  struct Alone {
    Start start;
    std::optional<FingerprintCheck> fp;
    std::vector<std::string> held_now, shaping, joint;
    std::size_t free_count = 0;  // the candidate's own free parameters
    EffectFit fit;
    bool promising = false;
    bool by_evidence = false;  // a found fingerprint or explained held drift: refitted whatever its rank
    std::string screen_note;
    double time_s = 0;
  };

  Start start_of(const std::vector<std::string>& ids) const;
  Alone fit_alone_phase(const std::vector<std::string>& ids);
  // Every set of the round that extends `selected`, fitted alone; the promising ones ranked by their alone
  // validation RMSE, and only the best ResidualOptions::joint_refits_per_round (plus any whose fingerprint was
  // found) keep their joint refit.
  void prepare_round(const std::vector<std::string>& selected);
  EffectFit finish(const std::vector<std::string>& ids, Alone a);
  const Recording& recording(const std::vector<std::string>& ids);
  SampleModelFactory replay(const std::vector<std::string>& ids, const std::string& warm_key,
                            const std::vector<RecordedField>& field) const;
  std::optional<FingerprintCheck> fingerprint_of(const std::string& candidate, const std::vector<std::string>& warm);
  // Holds the candidate's fingerprinted parameters in `start` (and in later rounds); returns their names.
  std::vector<std::string> hold_fingerprint(const std::string& candidate, const FingerprintCheck& fp, ParamSet* start);
  std::vector<std::string> held_of(const std::string& effect, const std::string& candidate,
                                   const std::vector<std::string>& held_now) const;
  // Once a pose effect is selected, every run of a joint refit that moves the form's state (its parameters
  // that are not field-only) or a pose reruns the form over every sample's whole path: in the rounds after it
  // these stay at the warm fit's values (the pose effect was fitted jointly with the form in its own round),
  // and the final refit frees them. Empty while `warm` has no pose effect.
  std::vector<std::string> shaping_held(const std::vector<std::string>& warm) const;
  ParamSet grid_start(const std::string& model_id, const std::vector<FitStage>& stages, const ParamSet& start) const;
  EffectFit fit_alone(const std::vector<std::string>& ids, const Start& start, const std::vector<FitStage>& stages);
  bool promising(const EffectFit& alone, const std::string& warm_key, const std::optional<FingerprintCheck>& fp,
                 std::string* screen_note, bool* by_evidence) const;
  // Fitted on `fit_on`'s calibration split (the search's subset, or the whole set) and scored on `score_on`.
  EffectFit joint_refit(const std::vector<std::string>& ids, const std::vector<std::string>& joint,
                        const ParamSet& from, const std::vector<FitSample>& fit_on, const ResidualInputs& score_on,
                        const FitOptions& fo);
  // The inputs the answer is refitted and scored on: SearchSubset::all, else the search's.
  const ResidualInputs& whole() const { return subset_.all != nullptr ? *subset_.all : in_; }
  // True when the search's costly fits saw fewer samples than the calibration split.
  bool subsampled() const { return subset_.calibration.size() < in_.calibration.size(); }
  void add_verdict(const std::string& candidate, const std::vector<std::string>& held_now,
                   const std::optional<FingerprintCheck>& fp, EffectFit* ef) const;
  void progress(const std::string& what) const;

  // Aliased, not copied: the inputs and options given to the constructor must outlive the search.
  const ResidualInputs& in_;
  const ResidualOptions& o_;
  FitOptions fo_;
  std::string form_;
  std::vector<std::string> form_free_;  // the form's joint parameters (none when the base is not fitted)
  std::vector<std::string> candidates_;
  SearchSubset subset_;
  std::map<std::string, EffectFit> fits_;
  std::map<std::string, Alone> alone_;           // this round's alone phases, by set key, until finished
  std::map<std::string, Recording> recordings_;  // the current warm start's only (recording())
  std::vector<FingerprintSample> fp_cal_, fp_val_;
  std::map<std::string, std::vector<std::string>> held_by_effect_;  // parameters a fingerprint settled (full names)
};

}  // namespace sb
