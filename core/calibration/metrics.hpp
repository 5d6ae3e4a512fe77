#pragma once
// The one definition of the field-error metrics, used by evaluate, fits and the GUI.
//
// For a set of (predicted, measured) marker fields over frames:
//  - a frame counts when at least one measured marker moves >= kMotionThresholdPx (frames where
//    nothing moves carry only tracking noise and would dilute the error);
//  - in a counted frame, every marker whose measurement is not NaN is a marker-frame;
//  - RMSE (px) = sqrt(mean over marker-frames of |pred - meas|^2);
//  - CS = mean over marker-frames with |meas| >= kMotionThresholdPx of cos(pred, meas), where a zero
//    prediction counts 0 (no direction is no agreement);
//  - n = number of marker-frames in the RMSE, n_cs = number in the CS.
// Accumulators merge, so per-sample results add up to per-motion and overall ones.
#include <map>
#include <string>
#include <vector>

#include "core/geometry/pose.hpp"

namespace sb {

inline constexpr double kMotionThresholdPx = 0.5;
// Below this norm (px) a prediction has no direction: its cosine counts 0.
inline constexpr double kZeroPredictionPx = 1e-12;

struct MetricsResult {
  double rmse_px = 0;  // NaN when n == 0
  double cs = 0;       // NaN when n_cs == 0
  long long n = 0;
  long long n_cs = 0;
};

class MetricsAccumulator {
 public:
  // Adds one frame; `pred` and `meas` hold one displacement per marker (sizes must match, else
  // std::invalid_argument). A non-finite prediction for a measured marker is counted in
  // invalid_predictions() and skipped.
  void add_frame(const std::vector<Vec2>& pred, const std::vector<Vec2>& meas);
  void merge(const MetricsAccumulator& other);
  MetricsResult result() const;
  long long frames_counted() const { return frames_; }
  long long invalid_predictions() const { return invalid_; }

 private:
  double sum_sq_ = 0;
  double sum_cos_ = 0;
  long long n_ = 0;
  long long n_cs_ = 0;
  long long frames_ = 0;
  long long invalid_ = 0;
};

// True for a frame the tracker recorded with every marker lost (NaN): nothing there to score, so a model may
// step through it without a field. An empty row is not such a frame (a size mismatch is an error elsewhere).
bool nothing_tracked(const std::vector<Vec2>& meas);

// Metrics of a single frame (the GUI's per-frame readout).
MetricsResult frame_metrics(const std::vector<Vec2>& pred, const std::vector<Vec2>& meas);

// Per-motion accumulators plus the overall one.
struct MotionMetrics {
  std::map<std::string, MetricsAccumulator> per_motion;
  MetricsAccumulator overall;
  void add(const std::string& motion, const MetricsAccumulator& acc);
  void merge(const MotionMetrics& other);
};

}  // namespace sb
