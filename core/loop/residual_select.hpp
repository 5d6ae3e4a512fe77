#pragma once
// Attribution of a model's residual to catalogued effects (docs/effects.md, "Selection rule").
//
// The caller owns the data and the fitting: fit_and_score(ids) wraps the base model with the effects
// `ids` (empty = the base model alone), fits the parameters on calibration data, and scores the fitted
// model on held-out validation samples. This module decides, from those scores only, which effects
// the data support: greedily, one at a time, each accepted only if
//   (1) the paired bootstrap interval of its validation RMSE improvement lies above a margin, and
//   (2) its BIC on the calibration data improves on the model it extends, and
//   (3) the caller did not veto the fit (FitResult::veto: a parameter at a bound is a verdict), and
//   (4) for an effect with a fingerprint (FitResult::fingerprint), the fingerprint was found on both splits
//       and agrees: the effect's main parameter is then the fingerprint's estimate, not a whole-field fit's.
// A fingerprint beyond model form replaces (1) and (2) by its own rule (FingerprintCheck::Acceptance).
// Selecting nothing is a valid outcome.
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/base/params.hpp"

namespace sb {

// Per validation sample (one unit of resampling: best a whole sequence, since the frames of one
// sequence are correlated): the sum of squared residual components and how many were summed.
struct ValidationErrors {
  std::vector<double> sq_err_px2;
  std::vector<double> count;
};

// A candidate effect's fingerprint (core/loop/fingerprints.hpp): its main parameter estimated, on each
// split, from evidence that is not the whole-field fit, and whether the two estimates make a finding.
struct FingerprintCheck {
  std::string evidence;                                           // what was looked at, for reports
  std::string param;                                              // the effect's main parameter ("tau_s")
  double calibration = std::numeric_limits<double>::quiet_NaN();  // the estimate on each split
  double validation = std::numeric_limits<double>::quiet_NaN();
  double signal_px = std::numeric_limits<double>::quiet_NaN();  // size of the evidence (calibration)
  bool consistent = false;  // found on both splits and agreeing: the fit uses `held` and `band`
  // The evidence lies where the base model's form error cannot reach (the held drift of a rate-independent
  // model): accepted on a positive gain without the interval margin. False when model-form error can mimic
  // the evidence (docs/effects.md), and the margin still applies.
  bool beyond_model_form = false;
  // How found evidence beyond model form is judged on validation. kHeldDrift (creep): its evidence lies in the
  // field, so the effect must explain the validation held drift (or pass the interval) and not make the whole
  // field certainly worse. kEvidence (the rest-grid lens): its evidence is not in the displacement field at
  // all (the rest positions, measured to a small fraction of k1), so the found effect is accepted on it, with
  // no veto; the whole-field gain is reported, not required: on the FE twin it measures how the base model's
  // form error leans on the lens (HydroShear + the true lens is certainly worse there, docs/effects.md).
  enum class Acceptance { kHeldDrift, kEvidence };
  Acceptance acceptance = Acceptance::kHeldDrift;
  std::string verdict;  // found / not found and why
  // When found: effect parameters (own names) held at these values ...
  std::vector<std::pair<std::string, double>> held;
  // ... and parameters whose whole-field fit (started as without a fingerprint) must end within [low, high]
  // around the estimate (evidence that model form can mimic: the fit must agree with it, else a veto).
  struct Band {
    std::string name;
    double estimate, low, high;
  };
  std::vector<Band> band;
};

struct FitResult {
  ValidationErrors validation;
  double calibration_sse_px2 = 0.0;  // sum of squared residuals on the calibration data after the fit
  double calibration_count = 0.0;    // residual components in that sum (> 0)
  std::size_t free_params = 0;       // parameters the fit adjusted
  ParamSet params;                   // the fitted table
  // Non-empty: this fit may not be accepted whatever its scores, and why (e.g. an effect parameter at a
  // bound of its physical range, or a candidate screened out before its joint refit).
  std::string veto;
  bool model_form_symptom = false;  // the veto is a bound: the effect patched the base model's form
  // The held-drift fingerprint on validation (docs/effects.md): over frames in which the indenter is held
  // still in the gel, the change of the field since the hold began, sum |dmeas - dpred|^2, sum |dmeas|^2
  // and the marker-frames summed. A rate-independent model predicts no change there, so its model-form
  // error cannot explain a measured drift; an effect that does has evidence of its own.
  double held_sse_px2 = 0, held_signal_px2 = 0, held_count = 0;
  std::optional<FingerprintCheck> fingerprint;  // set for effects that have one (the candidate of this fit)
};

using FitAndScore = std::function<FitResult(const std::vector<std::string>& effect_ids)>;

struct SelectionOptions {
  int bootstrap_resamples = 2000;
  std::uint64_t seed = 0x5eedbeefULL;  // the bootstrap is deterministic for a given seed
  double confidence = 0.95;            // two-sided percentile interval
  double min_lower_bound_pct = 1.0;    // accept only if the interval's lower bound exceeds this margin
  std::size_t max_effects = 2;         // greedy rounds
  // The held-drift fingerprint counts when the measured drift's RMS exceeds this (px; tracker noise is
  // 0.03-0.1 px per component) ...
  double min_fingerprint_signal_px = 0.15;
  // ... and a candidate that explains at least this fraction of its squared error (%) against the model it
  // extends is accepted on a positive point improvement and a better BIC, without the interval margin.
  double min_fingerprint_pct = 50.0;
};

struct Interval {
  double low = 0.0;
  double high = 0.0;
};

struct CandidateScore {
  std::string candidate;                // the effect tried in this round
  std::vector<std::string> effect_ids;  // the full set fitted: previous selection + candidate
  double reference_rmse_px = 0.0;       // the model it extends
  double rmse_px = 0.0;
  double improvement_pct = 0.0;  // 100 (reference - candidate) / reference, all samples
  Interval improvement_ci_pct;   // paired bootstrap over validation samples
  double delta_bic = 0.0;        // BIC(candidate) - BIC(reference) on calibration; < 0 is better
  bool accepted = false;         // passed both tests and had no veto (the round keeps the best accepted one)
  double fingerprint_pct = 0.0;  // held-drift error explained (%), NaN when the data hold no drift
  std::string veto;              // FitResult::veto of the candidate's fit
  bool model_form_symptom = false;
  std::optional<FingerprintCheck> fingerprint;  // FitResult::fingerprint of the candidate's fit
  std::string reason;                           // why it passed or failed, for reports
};

struct SelectionResult {
  std::vector<std::string> selected;  // in the order chosen; empty when nothing is supported
  FitResult base;                     // fit_and_score({})
  FitResult final_fit;                // fit_and_score(selected)
  double base_rmse_px = 0.0;
  double final_rmse_px = 0.0;
  std::vector<std::vector<CandidateScore>> rounds;  // every candidate tried, per greedy round
};

// sqrt(sum sq_err / sum count); throws std::invalid_argument for mismatched or empty vectors.
double validation_rmse(const ValidationErrors& e);
// Gaussian BIC: n ln(SSE / n) + k ln(n).
double gaussian_bic(double sse, double n, std::size_t k);
// Percentile interval of 100 (RMSE_ref - RMSE_cand) / RMSE_ref over `resamples` paired bootstrap
// resamples of the validation samples (the same sample indices for both). Throws std::invalid_argument
// when the two do not have the same number of samples.
Interval bootstrap_improvement_pct(const ValidationErrors& reference, const ValidationErrors& candidate, int resamples,
                                   std::uint64_t seed, double confidence);
// 100 (1 - held_sse(candidate) / held_sse(reference)): how much of the held drift the candidate explains;
// NaN when the validation data hold no drift above options.min_fingerprint_signal_px.
double fingerprint_explained_pct(const FitResult& reference, const FitResult& candidate,
                                 const SelectionOptions& options);
// Scores `candidate` against `reference` with the acceptance rule of the options.
CandidateScore score_candidate(const FitResult& reference, const FitResult& candidate, const SelectionOptions& options);

SelectionResult select_effects(const std::vector<std::string>& candidate_ids, const FitAndScore& fit_and_score,
                               const SelectionOptions& options = {});

}  // namespace sb
