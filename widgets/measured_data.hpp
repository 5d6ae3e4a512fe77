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
};

}  // namespace sb::ui
