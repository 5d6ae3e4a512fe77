#pragma once
// What the residual loop's steps share about samples (core/loop/residual.hpp): when a pose is held still,
// models built per sample, their scores on a split, a recorded base field replayed under effects, and the
// fingerprints' view of the samples.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/base/progress.hpp"
#include "core/calibration/fit.hpp"
#include "core/calibration/metrics.hpp"
#include "core/loop/fingerprints.hpp"
#include "core/models/model.hpp"

namespace sb {

// The one threshold of "held still": between two frames the indenter moved less than kHeldStillM (metres,
// any direction) and turned less than kHeldStillRad. It defines the held frames of the creep fingerprint and
// the held-drift score, the "held" loading state and the "hold" contact phase (a slower press or slide than
// 1 um per frame counts as held: at the datasets' 50-100 Hz that is under 0.1 mm/s).
inline constexpr double kHeldStillM = 1e-6;
inline constexpr double kHeldStillRad = 1e-5;
bool held_still(const Pose& before, const Pose& after);

// A model for sample i of a split (a fresh one per call).
using SampleModelFactory = std::function<std::unique_ptr<ShearModel>(const FitSample&, std::size_t)>;
// The model `model_id` (core/effects/model_spec.hpp: a form and effects) for every sample.
SampleModelFactory spec_model_factory(const std::string& model_id, const std::shared_ptr<const Sensor>& sensor);

// The same model for a fit's samples (run_fit_stages), by indenter.
FitModelFactory spec_fit_factory(const std::string& model_id, const std::shared_ptr<const Sensor>& sensor);

// Per-sample squared error and marker-frame count over the scored set, the metric accumulators and the
// held-drift sums (FitResult::held_*).
struct SplitScores {
  std::vector<double> sse, count;
  MotionMetrics metrics;
  double held_sse = 0, held_signal = 0, held_count = 0;
};
SplitScores score_samples(const SampleModelFactory& make, const ParamSet& params, const Sensor& sensor,
                          const std::vector<FitSample>& samples);

// A base model's field for every frame of one sample (displacements and contact flags).
using RecordedField = std::shared_ptr<const std::vector<FieldOutput>>;
// The field of `model_id` at `params` (names it does not know are ignored) for every sample.
std::vector<RecordedField> record_field(const std::string& model_id, const ParamSet& params,
                                        std::shared_ptr<const Sensor> sensor, const std::vector<FitSample>& samples);
// Effects `effect_ids` over a recorded field of the form `form_id` fitted at `form_params`: a fit that moves
// only effect parameters runs the effects alone (the form is the costly part, and its output does not depend
// on effect parameters). Valid only for the form parameters the field was recorded with. `recorded` must
// outlive the factory.
SampleModelFactory replay_factory(const std::string& form_id, const std::vector<std::string>& effect_ids,
                                  const ParamSet& form_params, const std::vector<RecordedField>* recorded,
                                  const std::shared_ptr<const Sensor>& sensor);

// The fingerprints' view of the samples, without a model's field: contact, held frames (held_still), the
// contact centre in the image and its travel since first contact.
std::vector<FingerprintSample> fingerprint_samples(const Sensor& sensor, const std::vector<FitSample>& samples);
// Sets pred_px of every sample of `*fs` to the field of `make`'s models at `params` for the scope's lifetime, and
// frees it at the end (the samples' measurements are not copied: at 10,000 samples a copy was gigabytes).
// @pre fs->size() == samples.size(); `*fs` outlives the scope.
class ModelFieldScope {
 public:
  ModelFieldScope(std::vector<FingerprintSample>* fs, const SampleModelFactory& make, const ParamSet& params,
                  const std::vector<FitSample>& samples);
  ~ModelFieldScope();
  ModelFieldScope(const ModelFieldScope&) = delete;
  ModelFieldScope& operator=(const ModelFieldScope&) = delete;

 private:
  std::vector<FingerprintSample>* fs_;
};

// A cancelled fit returns its last completed stage; the loop must not score that as a result: throws
// sb::Cancelled when `r` was cancelled or `progress` asks to.
void throw_if_cancelled(const CalibrationResult& r, const Progress& progress);

// The indices of `n` of `count` samples spread evenly over the split (index floor(i * count / n), i < n), every
// index when n is 0 or at least `count`. A split is stored in recording order, so the subset spans the collection.
std::vector<std::size_t> evenly_spaced(std::size_t count, std::size_t n);
std::vector<FitSample> subset(const std::vector<FitSample>& samples, const std::vector<std::size_t>& indices);

// Copies the values of the names both tables share.
void copy_shared(const ParamSet& from, ParamSet* to);

}  // namespace sb
