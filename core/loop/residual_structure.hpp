#pragma once
// The structure of a model's residual (measured - predicted) over a set of samples: RMS per bin of physical
// covariates (time since contact, loading state, distances, depth, travel, and in the contact's own frame),
// the mean residual field and its first principal component. The residual loop (residual.hpp) reports it
// for the base model and for the model it ends with.
#include <memory>
#include <string>
#include <vector>

#include "core/calibration/fit.hpp"

namespace sb {

// Whether the indenter's penetration grows, holds or shrinks at a frame (depth held: changes below kHeldStillM).
enum class LoadingState { kLoading, kDepthHeld, kUnloading, kNoContact };
// The contact's phase at a frame: with the depth held, still, or moving tangentially (a slide).
enum class ContactPhase { kLoading, kStill, kSlide, kUnloading, kNoContact };

// RMS of |residual| (px) per bin of one covariate.
struct CovariateTable {
  std::string name;
  std::string unit;
  std::vector<std::string> labels;  // bin labels ("0.00-0.25", or "loading" ...)
  std::vector<double> centre;       // bin centre (numeric covariates; index for categorical)
  std::vector<double> rms_px;       // NaN for an empty bin
  std::vector<long> count;          // marker-frames in the bin
  // Contact-frame tables only (in contact, a subset of the marker-frames): the mean residual component
  // along the direction from the contact centre to the marker (+: outward) and along the indenter's
  // tangential travel since first contact (+: the way it moved). Empty for the other tables.
  bool contact_frame = false;
  std::vector<double> mean_radial_px, mean_along_px;
};

// The mean residual field per bin of one frame covariate: a map per bin of where on the sensor, and which way,
// the model is wrong when the press is deep, the slide goes +x, the indenter tilts towards -y ...
struct BinnedMeanFields {
  std::string name;                        // "penetration depth (mm)", "travel direction", "tilt direction"
  std::vector<std::string> labels;         // one per bin
  std::vector<long> frames;                // scored frames in the bin
  std::vector<std::vector<Vec2>> mean_px;  // [bin][marker] mean residual (zero for an empty bin)
};

// A per-marker field in three numbers: its RMS over the markers, its mean (a shift of the whole field) and its
// longest arrow (px).
struct FieldSummary {
  double rms_px = 0, longest_px = 0;
  Vec2 shift_px = Vec2::Zero();
};
FieldSummary summarise_field(const std::vector<Vec2>& field_px);

struct ResidualStructure {
  double rmse_px = 0;
  long marker_frames = 0;
  long frames = 0;
  std::vector<CovariateTable> covariates;
  std::vector<double> explained_variance;  // first 3 principal components of the centred residual, fractions
  std::vector<Vec2> mean_field_px;         // per marker, mean residual over scored frames
  std::vector<Vec2> pc1_px;                // first component, scaled to its RMS amplitude (s1 / sqrt(frames))
  // Frames in contact binned by their depth (half as many equal widths as the covariate tables), by the direction of
  // the travel since first contact and by the direction the indenter's approach axis tilts (each: none, +x, +y, -x, -y
  // in E, which are the image's +u, +v, -u, -v): the mean residual per bin.
  std::vector<BinnedMeanFields> binned_fields;
};

// The residual structure of model `model_id` (core/effects/model_spec.hpp: a form and effects) at `params`
// over `samples`, with `bins` bins per numeric covariate.
ResidualStructure analyse_residual(const std::string& model_id, const ParamSet& params,
                                   std::shared_ptr<const Sensor> sensor, const std::vector<FitSample>& samples,
                                   int bins);
// The same over the samples pointed to (a subset of several splits, without copying them). @pre no null pointer.
ResidualStructure analyse_residual(const std::string& model_id, const ParamSet& params,
                                   std::shared_ptr<const Sensor> sensor, const std::vector<const FitSample*>& samples,
                                   int bins);

}  // namespace sb
