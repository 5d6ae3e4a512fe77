#pragma once
// The "RMSE over time" section: every model's RMSE against the measurement, frame by frame, computed on a
// worker thread (core/calibration/rmse_series) whenever the models' parameters change, drawn as one plot
// (core/workbench/timeline_plot: axes in s and px, a legend in the models' colours); a click or drag in it
// seeks the replay (AppState's queued seek) and its CSV button writes the plot beside the session file.
#include <string>
#include <vector>

#include "core/calibration/rmse_series.hpp"
#include "core/workbench/app_state.hpp"
#include "widgets/measured_data.hpp"

namespace sb::ui {

// A row drawn in place of a model's: the residual loop's answer where its panel shows it.
struct RmseRowOverride {
  int slot = -1;
  std::string title;
  std::vector<double> series;
};

class RmseSection {
 public:
  // A new sample: its series is computed afresh.
  void reset() { params_.clear(); }
  // Starts the series again when the models' parameters differ from those of the last request, once the
  // physics has applied them (no pending edits).
  void update(const AppSnapshot& snap, const AppState& state, const MeasuredData& measured);
  // `csv_path`: where the CSV button writes; `message`: the status bar's line, set when it has written.
  void draw(const AppSnapshot& snap, AppState& state, const std::string& csv_path, std::string& message,
            const RmseRowOverride& replaced = {}) const;
  // Blocks until the series is done (headless renders are deterministic).
  void wait() const;

 private:
  RmseSeriesJob job_;
  std::vector<std::vector<double>> params_;  // the parameter values the running/last job used
};

}  // namespace sb::ui
