#pragma once
// Closing the loop (`shearbench residual`): fit a shear model on the calibration split, look at the
// structure of its residual (measured - predicted) against physical covariates and by principal
// components, then attribute it to catalogued effects (core/loop/effects.hpp) with the selection rule of
// core/loop/residual_select.hpp, and report the validation error before and after.
//
// Scoring follows the field metric (core/calibration/metrics.hpp): frames where a measured marker moves >= 0.5 px,
// every finite marker in them. A validation "sample" for the bootstrap is a whole sequence; its count is
// marker-frames, so sqrt(sum sq / count) is the metric's RMSE. The calibration count given to the BIC is
// the number of scalar residual components (2 per marker-frame).
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/base/progress.hpp"
#include "core/calibration/fit.hpp"
#include "core/calibration/metrics.hpp"
#include "core/loop/residual_select.hpp"

namespace sb {

struct ResidualInputs {
  std::string dataset;                   // name, for reports
  std::string model_id;                  // base model (make_model id)
  std::shared_ptr<const Sensor> sensor;
  std::vector<FitSample> calibration;    // split "calibration" (fits see only these)
  std::vector<FitSample> validation;     // split "validation" (scores only)
  ParamSet base_params;                  // start of the base fit, or the fixed base when !fit_base
};

struct ResidualOptions {
  // true: fit the base model's joint parameters on calibration first, and refit them jointly with
  // every effect's parameters. false: the base parameters stay as given; only effect parameters are fit.
  bool fit_base = true;
  std::vector<std::string> candidates;   // effect ids to try; empty: the whole catalogue
  // Try the base model's model-form variants (model_form_variants) against it, each fitted jointly on
  // calibration and accepted by the same held-out rule as an effect (only with fit_base).
  bool model_forms = true;
  SelectionOptions selection;
  int max_iterations = 30;               // Levenberg-Marquardt iterations per stage
  // A candidate gets its joint refit (base + effects, every run a full model run) only when its effect
  // alone, over the reference's base field, improves the validation RMSE by at least this (%).
  double screen_min_pct = 0.5;
  int bins = 6;                          // per numeric covariate
  // Reports each fit as it starts; a set cancel flag ends the loop with sb::Cancelled (nothing returned).
  Progress progress;
};

// RMS of |residual| (px) per bin of one covariate.
struct CovariateTable {
  std::string name;
  std::string unit;
  std::vector<std::string> labels;       // bin labels ("0.00-0.25", or "loading" ...)
  std::vector<double> centre;            // bin centre (numeric covariates; index for categorical)
  std::vector<double> rms_px;            // NaN for an empty bin
  std::vector<long> count;               // marker-frames in the bin
  // Contact-frame tables only (in contact, a subset of the marker-frames): the mean residual component
  // along the direction from the contact centre to the marker (+: outward) and along the indenter's
  // tangential travel since first contact (+: the way it moved). Empty for the other tables.
  bool contact_frame = false;
  std::vector<double> mean_radial_px, mean_along_px;
};

struct ResidualStructure {
  double rmse_px = 0;
  long marker_frames = 0;
  long frames = 0;
  std::vector<CovariateTable> covariates;
  std::vector<double> explained_variance;  // first 3 principal components of the centred residual, fractions
  std::vector<Vec2> mean_field_px;         // per marker, mean residual over scored frames
  std::vector<Vec2> pc1_px;                // first component, scaled to its RMS amplitude (s1 / sqrt(frames))
};

// The residual structure of `params` over `samples` (the model is make_model(model_id) + `effects`).
ResidualStructure analyse_residual(const std::string& model_id, const std::vector<std::string>& effects,
                                   const ParamSet& params, std::shared_ptr<const Sensor> sensor,
                                   const std::vector<FitSample>& samples, int bins);

// The fit of one effect set, with its validation scores and metrics.
struct EffectFit {
  std::vector<std::string> effects;
  FitResult fit;                          // what select_effects sees
  MotionMetrics validation;               // per motion RMSE / CS of the fitted model
  double time_s = 0;
};

struct ResidualReport {
  std::string dataset;
  std::string model_id;
  bool fit_base = true;
  std::shared_ptr<const Sensor> sensor;
  ResidualStructure structure_before;     // base model, all samples (calibration + validation)
  ResidualStructure structure_after;      // selected model, all samples
  SelectionResult selection;
  std::map<std::string, EffectFit> fits;  // keyed by the ids joined with '+' ("" = base)
  // The model-form round (issue 17): each variant's fit and its score against the fitted base, and the
  // best accepted one ("" when none is). The effect rounds run on the base model either way.
  std::map<std::string, EffectFit> model_form_fits;
  std::vector<CandidateScore> model_form_scores;
  std::string model_form_selected;
  // How the selected variant was fitted: "" (its stages, then jointly) or the parameters held after their
  // first stage (model_form_hold), when held-out data preferred that fit; then the joint fit's RMSE too.
  std::vector<std::string> model_form_held;
  double model_form_joint_rmse_px = 0;
  EffectFit before, after;
  double time_s = 0;
};

std::string effect_set_key(const std::vector<std::string>& ids);

// The model-form corrections of `model_id` that are models of their own (docs/effects.md, "Model-form
// effects"): for hydroshear its layer, stick, layer+stick and contact variants; none for the others yet.
std::vector<std::string> model_form_variants(const std::string& model_id);
// The parameters the selected variant is also fitted with held after their first stage (FitOptions::hold):
// for hydroshear the dilation kernel (lambda_d, kappa_d), which none of its variants changes. Fitted
// jointly, the kernel can move to serve the shear frames; the loop keeps whichever fit held-out data prefers.
std::vector<std::string> model_form_hold(const std::string& model_id);

// The whole loop. Throws std::invalid_argument for empty splits or an unknown model / effect.
ResidualReport run_residual_loop(const ResidualInputs& in, const ResidualOptions& options);

// The effect's own parameters ("tau_s", ...) from a combined table (prefix removed).
nlohmann::ordered_json effect_params_json(const ParamSet& params, const std::string& effect_id);

nlohmann::ordered_json residual_to_json(const ResidualReport& r);
// Writes the PNG plots into `dir` named "<stem>_*.png" and returns their file names (not paths).
std::vector<std::string> write_residual_plots(const ResidualReport& r, const std::string& dir, const std::string& stem);
std::string residual_to_markdown(const ResidualReport& r, const std::vector<std::string>& plots);

}  // namespace sb
