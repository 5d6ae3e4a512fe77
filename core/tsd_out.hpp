#pragma once
// A small tsd/1 writer for the tracker and the importers (FORMAT.md): dataset.json, per sample poses.csv,
// markers.csv and optional frames/NNNNNN.png. Every file is written atomically (temporary file in the same
// directory, then rename). It writes exactly what FORMAT.md defines plus the sample's `extra` keys.
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/pose.hpp"

namespace sb {

struct TsdSampleOut {
  std::string id;
  std::string motion = "free";
  std::string indenter;  // empty: no "indenter" key (an unknown contact such as a fingertip)
  std::string split = "validation";
  double dt_s = 0.04;
  bool pose_known = false;
  std::vector<Pose> X_EI;                        // one per frame (placeholders when !pose_known)
  std::vector<std::vector<Vec2>> disp_px;        // [frame][marker], NaN = lost
  std::vector<cv::Mat> frames;                   // empty, or one image per frame
  nlohmann::json extra = nlohmann::json::object();  // extra keys of the sample entry (e.g. slip_label)
};

struct TsdDatasetOut {
  std::string name;
  std::string kind = "real";
  std::string provenance;
  std::string license;
  std::string sensor_model = "GelSight Mini";
  int width_px = 320, height_px = 240;
  double mm_per_px = 0.0634;
  Vec2 principal_px{159.5, 119.5};
  Vec2 gel_size_m{0.02525, 0.02075};
  double gel_thickness_m = 0.0045;
  std::vector<Vec2> markers_rest_px;
  nlohmann::json indenters = nlohmann::json::object();
  std::vector<std::pair<std::string, std::string>> mesh_files;  // (path relative to the dataset, OBJ text)
  std::vector<TsdSampleOut> samples;
};

// Writes `dataset` into `dir` (created if needed). Throws InputError naming the file that failed.
void write_tsd_dataset(const TsdDatasetOut& dataset, const std::string& dir);



}  // namespace sb
