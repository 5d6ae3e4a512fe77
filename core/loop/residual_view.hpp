#pragma once
// What the workbench shows of a residual analysis (`shearbench residual --json OUT.json`): the ranked
// effect candidates with their validation improvement and its 95 % interval, the selected effects with
// their fitted parameters, and the corrected model (base + selected effects) that the field panels can
// show beside the base model. No GL here, so it is unit-tested.
#include <atomic>
#include <future>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/models/model.hpp"

namespace sb {

struct ResidualCandidateView {
  std::string effect;
  double validation_rmse_px = 0;
  double improvement_pct = 0;
  double ci95_low_pct = 0, ci95_high_pct = 0;
  bool accepted = false;
  std::string reason;  // why it was (not) selected
  // The reason in two words, for a table: "found" (selected, its evidence found), "unshown cause" (selected, a
  // correction of unshown cause), "selected" (a report older than the evidence), "at a bound" (a model-form
  // symptom), "no evidence" (its fingerprint, the evidence where the effect shows, not found), "screened" (alone it
  // gained < 0.5 %), "vetoed", "within noise" (the interval or BIC rule), "not scored"; "not selected" in reports
  // older than the list of model-form symptoms, which did not record the rules.
  std::string verdict;
};

// One contact-frame table of the base model's residual (residual.hpp, CovariateTable::contact_frame).
struct ContactFrameTableView {
  std::string name, unit;
  std::vector<std::string> bins;
  std::vector<long> count;
  std::vector<double> rms_px, mean_radial_px, mean_along_px;
};

// One row of the input-response table (core/loop/input_response.hpp): how the measured field and the base
// model change when one known input changes (the first row: the fields at the reference inputs).
struct InputResponseRowView {
  std::string change;
  double measured_rms_px = 0, model_rms_px = 0, gain = 0, after_gain_rms_px = 0;
};

// One bin of the base model's mean residual per frame covariate (residual_structure.hpp, BinnedMeanFields): its
// frames, the RMS of the mean field over the markers, and its mean over them (a shift of the whole field).
struct BinnedMeanView {
  std::string covariate, bin;
  long frames = 0;
  double rms_px = 0;
  Vec2 shift_px = Vec2::Zero();
};

// A selected effect and its evidence (core/loop/effect_evidence.hpp): found, or a correction of unshown cause.
// Reports older than the evidence list only the ids: `recorded` false.
struct SelectedEffectView {
  std::string effect;
  bool recorded = false;
  bool found = false;
  std::string evidence;
};

// A parameter of the answer at a bound of its range (a model-form symptom of the answer itself).
struct AtBoundView {
  std::string param, bound;
  double value = 0;
  bool is_default = false;
};

struct ResidualSummary {
  std::string file;  // the JSON it came from
  std::string dataset;
  std::string model_id;       // the base model: hydroshear, fots, fots-reimpl, tacsl, tacsl-normalized
  double before_rmse_px = 0;  // validation split, base model
  double after_rmse_px = 0;   // validation split, the final model
  // The loop's answer (core/effects/model_spec.hpp): the selected model form (else the base) with the selected
  // effects. Reports older than the model-form round's effects on the form: model_id + selected.
  std::string after_model;
  std::string model_form;                         // the selected model form ("" when none was, or the report is older)
  std::vector<ResidualCandidateView> candidates;  // ranked: largest improvement first
  std::vector<std::string> selected;              // effect ids, in the order they wrap the form
  std::vector<SelectedEffectView> selected_evidence;  // the same, with each one's evidence
  // The answer with each effect labelled "(found)" or "(correction of unshown cause)"; after_model in older reports.
  std::string answer_labelled;
  std::vector<AtBoundView> answer_at_bound;          // empty in older reports, or none at a bound
  nlohmann::json before_params;                      // the base model fitted alone (or as given)
  nlohmann::json after_params;                       // the corrected model's whole parameter table
  std::vector<ContactFrameTableView> contact_frame;  // where and when the base is wrong (empty: older reports)
  std::vector<InputResponseRowView> input_response;  // the base model's responses (empty: older reports, or none)
  double inputs_only_rmse_px = 0;                    // what the inputs alone predict on validation (with the above)
  std::vector<BinnedMeanView> binned_means;          // the base's mean residual per bin (empty: older reports)
};

// Reads the residual JSON. Throws InputError naming the file and the JSON pointer of a missing or bad
// entry, or an unknown model / effect id.
ResidualSummary load_residual_summary(const std::string& path);

// The base model's parameters as the analysis fitted them (before any effect): the fair reference for
// the corrected model. Throws InputError when they do not fit the model's table.
ParamSet fitted_base_params(const ResidualSummary& summary);

// The corrected model: `after_model` at its fitted parameters (the form's own parameters included: they were
// refitted jointly with the effects when the analysis fitted the base).
std::unique_ptr<ShearModel> make_corrected_model(const ResidualSummary& summary, std::shared_ptr<const Sensor> sensor,
                                                 std::shared_ptr<const Indenter> indenter);

// measured - predicted per marker; NaN where the measurement is NaN (a marker the tracker lost) or
// the predicted field is shorter. Empty when `measured` is empty.
std::vector<Vec2> residual_field(const std::vector<Vec2>& measured, const std::vector<Vec2>& predicted);

// The fields of `model` (reset first) along `path`, one per step, computed on a worker thread so the
// UI never waits; starting again or destroying the job cancels the running computation.
class FieldSeriesJob {
 public:
  ~FieldSeriesJob();
  void start(std::unique_ptr<ShearModel> model, std::vector<Pose> path, double dt_s);
  void clear();
  bool running() const;
  // The finished series (empty while running or after clear()).
  const std::vector<std::vector<Vec2>>& result();
  void wait() const;

 private:
  std::atomic<bool> cancel_{false};
  std::future<std::vector<std::vector<Vec2>>> future_;
  std::vector<std::vector<Vec2>> result_;
};

}  // namespace sb
