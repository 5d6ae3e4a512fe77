#pragma once
// How the measured field and a model's field respond to the known inputs of a frame: the indenter's depth,
// tilt, tangential travel and twist, taken from the poses alone. Each field is regressed per marker on a
// polynomial of those inputs (a response surface), fitted on the calibration split; evaluating both
// surfaces at a reference input and one input changed at a time compares the data's response to each input
// with the model's (docs/sensors.md, "What the TacTip does that HydroShear does not"). The measured surface
// scored on the validation split is a physics-free reference: what the inputs alone predict.
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "core/calibration/fit.hpp"
#include "core/geometry/indenter.hpp"
#include "core/geometry/sdf.hpp"

namespace sb {

// The inputs of one frame, in E, from the poses (no model).
struct PoseInputs {
  double depth_m = 0;    // penetration of the indenter (indenter_penetration)
  Vec2 tilt{0, 0};       // xy of the indenter's approach axis R_EI z: (sin t) along the tilt's direction
  Vec2 travel_m{0, 0};   // xy translation since the first frame in contact (0 before contact)
  double twist_rad = 0;  // rotation about E's z since the first frame in contact
};
inline constexpr int kPoseInputCount = 6;
std::array<double, kPoseInputCount> as_array(const PoseInputs& x);
// Names and units of as_array's entries, for tables.
const std::array<const char*, kPoseInputCount>& pose_input_names();

// The inputs of every frame of one pose sequence. Throws std::invalid_argument for an empty sequence.
std::vector<PoseInputs> pose_inputs(const Sdf& gel_sdf_E, const Indenter& indenter, const std::vector<Pose>& X_EI);

// A per-marker polynomial of the inputs (every monomial up to `degree` of the six inputs, each scaled by its
// spread over the fitted frames), fitted by least squares on the frames where the marker is finite. The
// degree is lowered (to 1 at least) until the frames number at least ten per term; an input that spans less
// than its resolution (1 um, 1e-4 rad) counts as held and has no term.
class ResponseSurface {
 public:
  // fields[f][m]: frame f, marker m (NaN where not measured). Throws std::invalid_argument when the counts
  // differ or degree is outside [1, 3]. A marker finite in fewer frames than the polynomial has terms
  // predicts NaN.
  static ResponseSurface fit(const std::vector<PoseInputs>& inputs, const std::vector<std::vector<Vec2>>& fields,
                             int degree);
  std::vector<Vec2> predict(const PoseInputs& x) const;
  int terms() const { return static_cast<int>(exponents_.size()); }
  int degree() const { return degree_; }  // as asked, or lower when the frames are too few for its terms
  // An input's standard deviation over the fitted frames, 0 for one held (under its resolution: no term); its range.
  double spread(int i) const { return varies_[i] ? spread_[i] : 0.0; }
  double lo(int i) const { return lo_[i]; }
  double hi(int i) const { return hi_[i]; }
  // Whether every input of x lies inside the range it spanned in the fitted frames. Outside, a polynomial
  // grows without bound: analyse_input_response scores the inputs-only reference inside only.
  bool within_range(const PoseInputs& x) const;

 private:
  std::vector<double> features(const PoseInputs& x) const;
  std::vector<std::array<int, kPoseInputCount>> exponents_;
  int degree_ = 0;
  std::array<double, kPoseInputCount> centre_{}, spread_{};
  std::array<double, kPoseInputCount> lo_{}, hi_{};  // each input's range over the fitted frames
  std::array<bool, kPoseInputCount> varies_{};
  std::vector<std::vector<double>> coef_u_, coef_v_;  // [marker][term]; empty for a marker without enough data
};

// One input changed from the reference: the measured and the model's change of the field.
struct InputResponse {
  std::string input;                                 // "depth +1.0 mm", "tilt x +0.26" ...
  double measured_rms_px = 0;                        // RMS over markers of the measured change
  double model_rms_px = 0;                           // ... of the model's change
  double gain = 0;                                   // the scalar g minimising |measured - g model|
  double after_gain_rms_px = 0;                      // RMS of measured - g model: the change's shape error
  Vec2 measured_mean_px{0, 0}, model_mean_px{0, 0};  // mean over markers (a rigid shift of the field)
};

struct InputResponseAnalysis {
  PoseInputs reference;
  std::vector<InputResponse> responses;  // first the field at the reference itself (from no input), then one per input
  int degree_asked = 0;                  // the polynomial degree asked for
  int degree = 0;                        // the surfaces' own (ResponseSurface::degree: lower with few frames)
  double inputs_only_rmse_px = 0;        // the measured surface (calibration) scored on the validation frames
                                         // inside the calibration range (within_range)
  double model_rmse_px = 0;              // the model on the same validation marker-frames
  long validation_marker_frames = 0;
  long validation_frames = 0;
  long validation_frames_outside = 0;  // of those, frames with an input outside its calibration range: not scored
};

// One scored frame: its inputs, the measured and the model's field.
struct ScoredInputFrame {
  PoseInputs inputs;
  std::vector<Vec2> measured_px, model_px;
};

// Compares the responses from scored frames of the calibration split (surfaces fitted there) and scores the
// inputs-only reference on the validation split. The reference input: the median depth, every other input
// at 0 when 0 lies inside its calibration range (else its median); each step is one standard deviation of
// that input over the calibration frames. Throws std::invalid_argument for an empty split.
InputResponseAnalysis analyse_input_response(const std::vector<ScoredInputFrame>& calibration,
                                             const std::vector<ScoredInputFrame>& validation, int degree = 3);

// The scored frames of `samples` (frames with some marker measured, as the fit scores them) with model
// `model_id` (a form and effects) at `params`.
std::vector<ScoredInputFrame> scored_input_frames(const std::string& model_id, const ParamSet& params,
                                                  std::shared_ptr<const Sensor> sensor,
                                                  const std::vector<FitSample>& samples);

// The analysis as a Markdown section (a table of the responses, the reference and the floor).
std::string input_response_markdown(const InputResponseAnalysis& a, const std::string& model_id);

}  // namespace sb
