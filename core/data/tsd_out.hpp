#pragma once
// The tracker's and the importers' description of a dataset to write (FORMAT.md): poses as Pose, frames
// as images, indenter meshes as text. write_tsd_dataset turns it into a Dataset and writes it through
// tsd.hpp's write_dataset (the one writer of poses.csv, markers.csv and dataset.json) plus the frames
// (frames/NNNNNN.png) and meshes. Every file is written atomically.
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/geometry/pose.hpp"
#include "core/sensor/camera.hpp"
#include "core/sensor/sensor.hpp"

namespace sb {

struct TsdSampleOut {
  std::string id;
  std::string motion = "free";
  std::string
      indenter;  // a key of TsdDatasetOut::indenters (tsd/1 requires one; see import_common.cpp for unknown contacts)
  std::string split = "validation";
  double dt_s = 0.04;
  bool pose_known = false;
  std::vector<Pose> X_EI;                           // one per frame (placeholders when !pose_known)
  std::vector<std::vector<Vec2>> disp_px;           // [frame][marker], NaN = lost
  std::vector<cv::Mat> frames;                      // empty, or one image per frame (an empty Mat: a frame
                                                    // not imaged, every marker NaN; no file is written)
  nlohmann::json extra = nlohmann::json::object();  // extra keys of the sample entry (e.g. slip_label)
};

struct TsdDatasetOut {
  std::string name;
  std::string kind = "real";
  std::string provenance;
  std::string license;
  std::string sensor_model = kDefaultSensorModel;
  int width_px = 320, height_px = 240;
  double mm_per_px = 0.0634;
  Vec2 principal_px{159.5, 119.5};
  Vec2 gel_size_m{0.02525, 0.02075};
  double gel_thickness_m = 0.0045;
  // A camera that replaces the orthographic one above (width_px .. principal_px), e.g. the TacTip's pinhole.
  std::optional<Camera> camera;
  std::string gel_surface = "flat";     // or "spherical_cap" (a mesh file is not written by importers)
  double gel_radius_m = 0.0;            // spherical_cap only
  double gel_footprint_radius_m = 0.0;  // spherical_cap only
  double markers_depth_m = 0.0;         // pins below the contact surface
  std::vector<Vec2> markers_rest_px;
  nlohmann::json sensor_extra = nlohmann::json::object();  // further keys of "sensor" (e.g. a TacTip's description)
  nlohmann::json indenters = nlohmann::json::object();
  std::vector<std::pair<std::string, std::string>> mesh_files;  // (path relative to the dataset, OBJ text)
  std::vector<TsdSampleOut> samples;
};

// Writes `dataset` into `dir` (created if needed). Throws InputError naming the file that failed.
void write_tsd_dataset(const TsdDatasetOut& dataset, const std::string& dir);

}  // namespace sb
