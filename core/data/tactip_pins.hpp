#pragma once
// A TacTip split's images read, and their pins tracked against the prior and checked for lattice slips.
#include <cstddef>
#include <filesystem>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/data/import_tactip.hpp"
#include "core/data/tactip_targets.hpp"
#include "core/tracking/lattice_check.hpp"
#include "core/tracking/pin_field_prior.hpp"
#include "core/tracking/pin_tracker.hpp"

namespace sb {

// A grey image, mirrored left-right when the sensor says its camera sees the tool axes mirrored (so that E,
// whose x/y are the image's u/v, stays right-handed). InputError(path) when it cannot be read.
cv::Mat read_tactip_image(const std::string& path, bool mirror = false);

// One split's targets and the pins detected in each of its images.
struct TactipSplit {
  std::string name;
  std::vector<TactipTarget> targets;
  std::vector<std::vector<PinDetection>> detections;
};
// The images of split `name` under `in`, each the reference's size; a differing images/image_0.png of another
// split is said in `report` (the calibration split's is the rest).
TactipSplit read_tactip_split(const std::filesystem::path& in, const std::string& name,
                              std::vector<TactipTarget> targets, const PinReference& ref, const cv::Mat& ref_img,
                              bool mirror, const TactipImportOptions& options, ImportReport& report);
// The targets of one split, the first max_samples_per_split rows when set.
std::vector<TactipTarget> read_split_targets(const std::filesystem::path& in, const std::string& name,
                                             const TactipImportOptions& options);

// The prior of every sample's pin field, fitted on the calibration split alone by continuation in depth.
ContinuationResult fit_tactip_prior(const PinReference& ref, const TactipSplit& cal,
                                    const TactipImportOptions& options);
// One report line per stage of the prior's fit (or why there is none).
void report_prior(const ContinuationResult& fit, std::size_t calibration_samples, ImportReport& report);

// One image's pins: tracked against the prior, then checked; the pins the check doubts are lost, not
// kept (a kept pin must be the right pin), unless options.lattice_check is off.
struct CheckedPins {
  std::vector<Vec2> disp;
  LatticeCheckResult check;
  int suspect = 0;  // tracked pins the check doubts
  int kept() const {
    int n = 0;
    for (const auto& d : disp) n += d.allFinite();
    return n;
  }
};
CheckedPins track_checked(const PinReference& ref, const std::vector<PinDetection>& detections,
                          const std::vector<Vec2>& prior, const TactipImportOptions& options);
// The check's counts for the sample's "lattice_check" field; `dropped`: whether the suspects were dropped.
nlohmann::json lattice_check_json(const CheckedPins& pins, std::size_t detections, bool dropped);

}  // namespace sb
