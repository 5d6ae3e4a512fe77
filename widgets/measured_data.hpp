#pragma once
// Measured marker data of the replayed sample, as the workbench's sections read it.
#include <string>
#include <vector>

#include "core/geometry/pose.hpp"

namespace sb::ui {

// Measured marker data of the replayed sample, frame by frame (frame k goes with step k).
struct MeasuredData {
  std::vector<std::vector<Vec2>> disp_px;  // per frame, per marker; NaN for a marker the tracker lost
  std::vector<std::string> frame_paths;    // per frame PNG; empty when the dataset has no frames
  std::vector<Pose> poses;                 // the sample's pose path X_EI (for RMSE over time)
  std::string label = "Measured";
  // The other sensors of a multi-sensor log (dataset.json "shearbench": {"sensors": [sample ids]}, e.g. the
  // two pads of a grasp), recorded at the same frames: each drawn in a panel of its own beside this one.
  struct Beside {
    std::string label;
    std::vector<std::vector<Vec2>> disp_px;  // per frame, per marker
  };
  std::vector<Beside> beside;
};

}  // namespace sb::ui
