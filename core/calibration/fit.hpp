#pragma once
// Staged least-squares calibration of a shear model against measured marker displacements (bounded_lm.hpp).
//
// A fit minimises, over the parameters of one stage at a time,
//   L(theta) = 1/2 sum_{(k,j) in A} rho(|s * pred_kj(theta) - meas_kj|^2)      (pred, meas in px)
// where A are the marker-frames the fidelity metric scores (active_marker_frames), rho is the identity
// or a robust loss (Huber / Cauchy), and s = 1 except in "rescale" stages, where s is the closed-form
// best scale <pred, meas> / <pred, pred> (the stage fits the shape of the field, not its size).
// Parameters are optimised in log space when their ParamSpec says log_scale, always inside the spec's
// [min, max]. Each stage first scans a small data-independent grid around the spec defaults (so a bad
// start cannot trap it on a plateau, e.g. mu so large that nothing slips), then runs Levenberg-Marquardt
// from the best point. Samples run in parallel (TBB), one model instance each; results are deterministic.
//
// The split rule lives in one place: fit_model refuses any sample whose split is not "calibration", and
// load_calibration_samples (fit_data.hpp) never reads the others.
//
// Two files: the engine (fit_engine.cpp: run_fit_stages, the minimiser's calls, progress and cancel) and the
// policy (fit.cpp: a model's stages, the joint refinement, fit_model), whose per-family part is the family's
// descriptor (core/models/model_family.hpp).
#include <atomic>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/calibration/metrics.hpp"
#include "core/geometry/indenter.hpp"
#include "core/models/model.hpp"
#include "core/models/model_family.hpp"
#include "core/sensor/sensor.hpp"

namespace sb {

// A marker that moved at least this far (px) in a frame makes the frame active (the metric's rule).
inline constexpr double kActiveFramePx = kMotionThresholdPx;

// One calibration sample, loaded: the indenter pose per frame and the measured displacement per
// frame and marker (NaN where the tracker lost the marker).
struct FitSample {
  std::string id;
  std::string motion;  // dilation | shear | twist | roll | slip | free
  std::string split = "calibration";
  double dt_s = 0.02;
  std::vector<Pose> X_EI;                  // [frame]
  std::vector<std::vector<Vec2>> meas_px;  // [frame][marker]
  std::shared_ptr<const Indenter> indenter;
};

// The scored marker-frames of one sample: frames in which some measured marker moved >= kActiveFramePx,
// and in them every marker whose measurement is finite. Flat indices frame * n_markers + marker.
std::vector<int> active_marker_frames(const std::vector<std::vector<Vec2>>& meas_px);

// FitStage, one stage of a model's calibration procedure: core/models/model_family.hpp (a family's descriptor
// holds its forms' stage tables).

// The stage table of a model id (throws std::invalid_argument for an unknown id). A form with effects
// (core/effects/model_spec.hpp) has the form's stages, then one stage of the effects' parameters on every motion.
std::vector<FitStage> fit_stages(const std::string& model_id);
// The joint refinement: every parameter of the stages (plus the image scale when px_scale), on every
// motion the stages use, without rescaling.
FitStage joint_stage(const std::string& model_id, bool px_scale);
// FitOptions::hold: each held parameter leaves every stage after the first that lists it; a stage left with
// no parameters is dropped.
void hold_after_first_stage(const std::vector<std::string>& hold, std::vector<FitStage>* stages);

enum class RobustLoss { kNone, kHuber, kCauchy };
// "none" | "huber" | "cauchy"; throws std::invalid_argument otherwise.
RobustLoss parse_robust_loss(const std::string& name);
std::string to_string(RobustLoss loss);

struct FitProgress {
  std::string stage;
  int iteration = 0;
  double loss = 0;  // least-squares cost 1/2 sum rho
};

struct StageReport;
struct CalibrationResult;

struct FitOptions {
  std::vector<std::string> stages;  // names to run, in table order; empty: all
  bool joint = false;               // append the joint refinement
  bool fit_px_scale =
      false;  // joint also fits the image scale (fots: px_per_mm; the others' px/m gains are stage params)
  // Parameters fitted only in the first stage that lists them: later stages and the joint refinement keep
  // them (a stage left with none is skipped). E.g. {lambda_d, kappa_d}: the dilation kernel as the presses
  // fit it, not moved to serve the shear frames.
  std::vector<std::string> hold;
  RobustLoss robust = RobustLoss::kNone;
  double robust_scale_px = 1.0;  // where the robust loss bends
  int max_iterations = 50;       // per stage
  // A stage stops when a step changes the cost by less than this fraction of it (BoundedLmOptions).
  double function_tolerance = 1e-6;
  bool coarse_scan = true;
  std::function<void(const FitProgress&)> progress;
  // Checked between iterations (and between model runs); a cancelled stage is discarded, so the
  // result holds the parameters of the last completed stage.
  const std::atomic<bool>* cancel = nullptr;
  // Called after every completed stage with the result so far (the CLI writes its file there).
  std::function<void(const CalibrationResult&)> on_stage_done;
};

struct StageReport {
  std::string name;
  std::vector<std::string> params;
  std::vector<std::string> motions;  // motions actually used
  int samples = 0;
  int residuals = 0;                             // scored marker-frames
  double loss_before = 0, loss_after = 0;        // least-squares cost at the stage's start and end
  double rmse_before_px = 0, rmse_after_px = 0;  // sqrt(mean |s pred - meas|^2) over the scored set
  double scale = 1;                              // the rescale factor s (rescale stages)
  int iterations = 0;
  int evaluations = 0;  // model runs over the stage's samples
  double time_s = 0;
  std::string termination;
  std::string note;  // e.g. "no slip samples: fitted on shear"
  bool skipped = false;
};

struct CalibrationResult {
  std::string model_id;
  ParamSet params;
  std::vector<StageReport> stages;
  bool cancelled = false;
  double time_s = 0;
  nlohmann::json report_json() const;  // stages, losses, iterations, times
};

// Throws std::invalid_argument naming the first sample whose split is not "calibration".
void require_calibration_split(const std::vector<FitSample>& samples);

// Makes one model instance for a sample's indenter (each sample gets its own).
using FitModelFactory = std::function<std::unique_ptr<ShearModel>(std::shared_ptr<const Indenter>)>;

// The engine: runs `stages` in order from `start` (options.stages / joint are ignored here). Usable with
// any ShearModel, which is how the minimiser is tested on its own.
CalibrationResult run_fit_stages(const std::string& model_id, const FitModelFactory& make,
                                 const std::vector<FitStage>& stages, const std::vector<FitSample>& samples,
                                 const ParamSet& start, const FitOptions& options);
// Makes the model of samples[index] (a model that may depend on the sample, e.g. one replaying a
// recorded base-model field while only effect parameters are fitted, core/loop/residual.cpp).
using FitSampleModelFactory = std::function<std::unique_ptr<ShearModel>(const FitSample&, std::size_t index)>;
CalibrationResult run_fit_stages_per_sample(const std::string& model_id, const FitSampleModelFactory& make,
                                            const std::vector<FitStage>& stages, const std::vector<FitSample>& samples,
                                            const ParamSet& start, const FitOptions& options);

// Runs the stages of `model_id` from `start` (the table, filtered by options.stages, plus the joint stage). Throws
// std::invalid_argument for unknown stage names or parameters, and when a sample is not from the calibration split.
CalibrationResult fit_model(const std::string& model_id, std::shared_ptr<const Sensor> sensor,
                            const std::vector<FitSample>& samples, const ParamSet& start, const FitOptions& options);

// The model's prediction for every frame of a sample (the model is reset first). A frame whose measured
// markers are all NaN (recorded, nothing tracked: the TacTip's slide frames before its one image) is stepped
// without a field (ShearModel::step with nullptr) and predicted as NaN.
bool frame_unmeasured(const FitSample& sample, std::size_t k);
std::vector<std::vector<Vec2>> simulate_sample(ShearModel& model, const FitSample& sample);
// Steps `model` (not reset) through frames first.. of `sample` into (*out)[k] (sized to the sample's frames), as
// simulate_sample does; before_frame(k), when given, is called before each step.
void simulate_frames(ShearModel& model, const FitSample& sample, std::size_t first, std::vector<std::vector<Vec2>>* out,
                     const std::function<void(std::size_t)>& before_frame = {});

// RMSE (px) of `params` over the scored marker-frames of `samples` (no robust loss, no rescale).
double fit_rmse_px(const std::string& model_id, const std::shared_ptr<const Sensor>& sensor,
                   const std::vector<FitSample>& samples, const ParamSet& params);

}  // namespace sb
