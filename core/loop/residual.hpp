#pragma once
// Closing the loop (`shearbench residual`, docs/effects.md "The loop, step by step"): a pipeline of five
// named steps, each a method of ResidualLoop with its inputs and outputs as types:
//   1. fit_base           the base model fitted on the calibration split            -> EffectFit ("before")
//   2. model_form_round   each model-form variant of the base, fitted and scored   -> ModelFormRound
//                         against it on validation; the best accepted one is the form the effects build on
//   3. effect_rounds      the catalogued effects (core/effects) on top of that form, -> EffectRounds
//                         greedily, by the selection rule of residual_select.hpp (with fingerprints)
//   4. final_fit          the form plus the selected effects, fitted jointly        -> FinalModel ("after")
//   5. score              the residual structure of "before" and "after"           -> both ResidualStructures
// "before" is the base model as fitted; "after" is the model the analysis found, a model by name
// (core/effects/model_spec.hpp) that every other command and the workbench load.
//
// Scoring follows the field metric (core/calibration/metrics.hpp): frames where a measured marker moves >= 0.5 px,
// every finite marker in them. A validation "sample" for the bootstrap is a whole sequence; its count is
// marker-frames, so sqrt(sum sq / count) is the metric's RMSE. The calibration count given to the BIC is
// the number of scalar residual components (2 per marker-frame).
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/base/progress.hpp"
#include "core/calibration/fit.hpp"
#include "core/calibration/metrics.hpp"
#include "core/loop/evidence.hpp"
#include "core/loop/input_response.hpp"
#include "core/loop/residual_select.hpp"
#include "core/loop/residual_structure.hpp"

namespace sb {

struct ResidualInputs {
  std::string dataset;   // name, for reports
  std::string model_id;  // base model (a model_ids() entry)
  std::shared_ptr<const Sensor> sensor;
  std::vector<FitSample> calibration;  // split "calibration" (fits see only these)
  std::vector<FitSample> validation;   // split "validation" (scores only)
  ParamSet base_params;                // start of the base fit, or the fixed base when !fit_base
};

struct ResidualOptions {
  // true: fit the base model's joint parameters on calibration first, and refit them jointly with
  // every effect's parameters. false: the base parameters stay as given; only effect parameters are fit.
  bool fit_base = true;
  std::vector<std::string> candidates;  // effect ids to try; empty: the whole catalogue
  // Try the base model's model-form variants (model_form_variants) against it, each fitted jointly on
  // calibration and accepted by the same held-out rule as an effect (only with fit_base).
  bool model_forms = true;
  SelectionOptions selection;
  int max_iterations = 30;  // Levenberg-Marquardt iterations per stage
  // A candidate gets its joint refit (form + effects, every run a full model run) only when its effect
  // alone, over the reference's recorded field, improves the validation RMSE by at least this (%).
  double screen_min_pct = 0.5;
  // Of a round's candidates that pass that screen, only this many, the best alone, get the joint refit (those
  // whose fingerprint was found or that explain the held drift always do); the rest are reported as screened.
  std::size_t joint_refits_per_round = 3;
  // The subset rule. Every fit after the base's (a model-form variant's, each candidate effect's alone fit and
  // grid start, each joint refit) sees at most this many calibration samples, evenly spaced (evenly_spaced; 0: all
  // of them): they screen and rank. Every score the selection rule and the report use (the BIC's calibration error,
  // validation, the bootstrap) uses every sample of both splits, and the answer is refitted on the whole calibration
  // split (EffectSearch::final_refit). On the real TacTip a run of HydroShear over its 1000 calibration samples
  // costs ~0.5 s and a joint refit hundreds.
  std::size_t search_samples = 250;
  // The residual structure (step 5: covariate tables, principal components, binned mean fields) is a description
  // of the residual, not a score: it sees at most this many samples of both splits together, evenly spaced over
  // each split in proportion to its size (0: all). The shipped TacTip set (1999 samples) is seen whole.
  std::size_t structure_samples = 2000;
  // The search set: the search (the model-form round and the effect rounds: every fit, score, fingerprint and
  // bootstrap by which candidates are ranked, accepted or refused) sees at most this many samples of both splits
  // together, evenly spaced over each split in proportion to its size (0: all). When that is fewer than the set,
  // the base and the answer are refitted jointly from the search's values on every calibration sample, and their
  // scores and the answer's evidence use every sample; their responses to the inputs (a description, like the
  // structure) the search set's.
  // The shipped TacTip set (1999 samples) is searched whole.
  std::size_t search_set = 2000;
  // Those refits on every calibration sample start at the search's optimum and stop when a step gains less than
  // this fraction of the cost: 1e-4 of the squared error is 0.005 % of the RMSE, far inside the selection rule's
  // 1 % margin, and a refit of 5005 TacTip samples costs some 4 s a model run (20 a Jacobian).
  double refit_on_all_tolerance = 1e-4;
  int bins = 6;  // per numeric covariate
  // Reports each fit as it starts; a set cancel flag ends the loop with sb::Cancelled (nothing returned).
  Progress progress;
};

// The fit of one model (a form, or a form with effects), with its validation scores and metrics.
struct EffectFit {
  std::vector<std::string> effects;
  FitResult fit;             // what select_effects sees
  MotionMetrics validation;  // per motion RMSE / CS of the fitted model
  double time_s = 0;
};

// Step 2's output: each variant's fit and its score against the fitted base.
struct ModelFormRound {
  std::map<std::string, EffectFit> fits;
  std::vector<CandidateScore> scores;
  std::string selected;  // the best accepted variant; "" when none is
  // How the selected variant was fitted: {} (its stages, then jointly) or the parameters held after their
  // first stage (model_form_hold), when held-out data preferred that fit; then the joint fit's RMSE too.
  std::vector<std::string> held;
  double joint_rmse_px = 0;
};

// Step 3's output: the greedy selection of effects on top of `form`.
struct EffectRounds {
  std::string form;  // the model the effects wrap: the selected form, else the base
  SelectionResult selection;
  std::map<std::string, EffectFit> fits;  // keyed by effect_set_key ("" = the form as fitted)
  // The selected set fitted with everything free once more, on every calibration sample, when the rounds after
  // a pose effect held the form's state and the pose or fitted it on a subset (EffectSearch::final_refit); empty
  // when the selected set's fit already was joint and on every sample. `final_refit_why` says which.
  std::optional<EffectFit> final_refit;
  std::string final_refit_why;
};

// Step 4's output: the loop's answer.
struct FinalModel {
  std::string model_id;  // "<form>+<effect>+..." (core/effects/model_spec.hpp)
  EffectFit fit;
};

// A fitted parameter at a bound of its range (within kAtBoundFraction of it; of the log range for log-scale specs).
struct ParamAtBound {
  std::string name;  // the answer's table name ("hydroshear.mu", "skin_indentation.spread_m")
  double value = 0;
  bool upper = false;
  bool is_default = false;  // the bound is the parameter's "no effect" default (the effect switched itself off)
};

struct ResidualReport {
  std::string dataset;
  std::string model_id;  // the base model
  bool fit_base = true;
  // Calibration samples the search's form-rerunning fits saw (ResidualOptions::search_samples) and the split's.
  std::size_t search_samples = 0, calibration_samples = 0;
  // Samples the residual structure saw (ResidualOptions::structure_samples) and the two splits' together.
  std::size_t structure_samples = 0, all_samples = 0;
  // Samples of both splits the search saw (ResidualOptions::search_set): the model-form round's and the effect
  // rounds' scores are on these; `before` and `after` on all_samples.
  std::size_t search_set_samples = 0;
  std::shared_ptr<const Sensor> sensor;
  EffectFit before;  // the base model as fitted
  ModelFormRound model_form;
  EffectRounds effects;
  std::string after_model;  // the final model by name
  EffectFit after;          // its joint fit and scores
  // Step 6: each selected effect's evidence (effect_evidence.hpp), in the order of effects.selection.selected:
  // found, or a correction of unshown cause. The answer's name, headline and JSON say which is which.
  std::vector<EffectEvidence> evidence;
  // The answer's free parameters (its form's and its effects') at a bound of their range: model-form symptoms
  // of the answer itself (answer_at_bound).
  std::vector<ParamAtBound> answer_at_bound;
  ResidualStructure structure_before;  // base model, all samples (calibration + validation)
  ResidualStructure structure_after;   // final model, all samples
  // How the measured field and each model respond to the known inputs (input_response.hpp); empty when a
  // split has no scored frame.
  std::optional<InputResponseAnalysis> response_before, response_after;
  double time_s = 0;
};

std::string effect_set_key(const std::vector<std::string>& ids);

// The parameters of `params` named in `free` that sit at a bound of their range.
std::vector<ParamAtBound> params_at_bounds(const ParamSet& params, const std::vector<std::string>& free);

// The answer's name with each effect labelled: "hydroshear-contact + tool_frame (correction of unshown cause)";
// found effects carry "(found)". The model id to load stays ResidualReport::after_model.
std::string labelled_answer(const ResidualReport& r);
// The selected effects whose evidence was found (found = true) or not (found = false), in selection order.
std::vector<std::string> effects_by_evidence(const ResidualReport& r, bool found);

// The model-form corrections of `model_id` that are models of their own (docs/effects.md, "Model-form
// effects"), as its family's descriptor lists them (core/models/model_family.hpp) when `model_id` is the family's
// base form: for hydroshear its layer, stick, layer+stick and contact variants; none for the others yet.
std::vector<std::string> model_form_variants(const std::string& model_id);
// The parameters the selected variant is also fitted with held after their first stage (FitOptions::hold), the
// family descriptor's hold list: for hydroshear the dilation kernel (lambda_d, kappa_d), which none of its variants
// changes. Fitted jointly, the kernel can move to serve the shear frames; the loop keeps whichever fit held-out data
// prefers.
std::vector<std::string> model_form_hold(const std::string& model_id);

class ResidualLoop {
 public:
  // Throws std::invalid_argument for empty splits or an unknown model / effect.
  ResidualLoop(const ResidualInputs& in, const ResidualOptions& options);

  EffectFit fit_base() const;
  ModelFormRound model_form_round(const EffectFit& base) const;
  // The form the effect rounds build on: the selected variant's fit, else the base's.
  EffectRounds effect_rounds(const std::string& form, const EffectFit& form_fit) const;
  FinalModel final_fit(const EffectRounds& rounds) const;
  ResidualStructure score(const std::string& model_id, const EffectFit& fit) const;
  std::optional<InputResponseAnalysis> input_response(const std::string& model_id, const EffectFit& fit) const;
  // Every step in order.
  ResidualReport run() const;

 private:
  // One fitted model's scores on both splits (what `fit` of EffectFit needs besides the parameters).
  // scored: on the search's inputs (search_in); scored_on_all: on every sample.
  EffectFit scored(const std::string& model_id, std::vector<std::string> effects, const ParamSet& params,
                   std::size_t free_params) const;
  EffectFit scored_on_all(const std::string& model_id, std::vector<std::string> effects, const ParamSet& params,
                          std::size_t free_params) const;
  // The inputs the search sees: the search set when ResidualOptions::search_set is smaller than the set, else all.
  const ResidualInputs& search_in() const { return search_set_ ? *search_set_ : in_; }
  bool searched_on_part() const { return search_set_.has_value(); }
  // The base fitted on the search set, refitted (its joint stage, from those values) and scored on every sample.
  EffectFit base_on_all(const EffectFit& searched) const;
  FitOptions fit_options() const;
  std::vector<std::string> answer_free_params(const ResidualReport& rep) const;
  EffectFit fit_variant_alone(const std::string& v, const EffectFit& base) const;
  EffectFit fit_variant(const std::string& v, const EffectFit& base, const std::vector<std::string>& hold) const;

  // Aliased, not copied: the inputs and options given to the constructor must outlive the loop.
  const ResidualInputs& in_;
  const ResidualOptions& o_;
  std::vector<std::string> candidates_;
  std::optional<ResidualInputs> search_set_;  // ResidualOptions::search_set's samples, when fewer than the set's
  std::vector<FitSample> search_cal_;         // the calibration samples the search's costly fits see (search_samples)
  std::vector<const FitSample*> structure_samples_;  // the samples step 5's structure sees (structure_samples)
};

// The whole loop: ResidualLoop(in, options).run().
ResidualReport run_residual_loop(const ResidualInputs& in, const ResidualOptions& options);

// The effect's own parameters ("tau_s", ...) from a combined table (prefix removed).
nlohmann::ordered_json effect_params_json(const ParamSet& params, const std::string& effect_id);

// The report's JSON, Markdown and plots: residual_report.hpp.

// The final model as a parameter file ({"<after_model>": {name: value}}) that `evaluate --params`,
// `simulate --params` and the workbench load.
nlohmann::ordered_json final_model_params_json(const ResidualReport& r);

}  // namespace sb
