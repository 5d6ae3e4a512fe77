#pragma once
// A model's predicted marker field along a pose path, written as a tsd/1 dataset (one sample: the poses,
// the predicted markers.csv, the indenter mesh under meshes/), so predictions and measurements share one
// format. Used by `shearbench simulate` and the workbench's field export.
#include <atomic>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/geometry/pose.hpp"
#include "core/models/model.hpp"

namespace sb {

struct PredictionExport {
  std::string name;  // dataset name
  std::string sample_id;
  std::string motion = "free";
  std::string provenance;     // what produced it (model, parameters, source), in words
  nlohmann::json shearbench;  // machine-readable provenance: {"model", "params", ...}
  std::shared_ptr<const Sensor> sensor;
  std::shared_ptr<const Indenter> indenter;
  double dt_s = 0.02;
  std::vector<double> t_s;                 // per frame; empty: k dt
  std::vector<Pose> X_EI;                  // per frame
  std::vector<std::vector<Vec2>> disp_px;  // per frame, per marker
};

// Writes the dataset into `dir` (meshes first, then the sample, then dataset.json: a reader never sees a
// dangling reference; every file atomically). Throws std::invalid_argument when the frame counts differ.
void write_prediction_dataset(const std::string& dir, const PredictionExport& e);

// Steps `model` (reset first) along `path` and returns its field at every pose; empty when `cancel`
// is set before the end. `on_steps`, when given, is called with the number of steps done every
// kPredictReportEvery steps and once at the end (progress bars).
inline constexpr std::size_t kPredictReportEvery = 64;
std::vector<std::vector<Vec2>> predict_along(ShearModel& model, const std::vector<Pose>& path, double dt_s,
                                             const std::atomic<bool>* cancel = nullptr,
                                             const std::function<void(std::size_t)>& on_steps = {});

}  // namespace sb
