#pragma once
// The TacTip shear set importer (raw/tactip_shear): pins tracked, the sensor identified, one tsd/1 dataset.
#include <limits>
#include <string>

#include "core/data/import_common.hpp"
#include "core/tracking/pin_tracker.hpp"

namespace sb {

// raw/tactip_shear (SOURCE.md): one dataset, the reference image (images/image_0.png) as the rest, every
// targets.csv row one sample (calibration/ -> split calibration, validation/ -> validation) whose poses.csv
// is the collection procedure (above, pressed, slid to the final pose) and whose markers.csv is zero at
// frame 0 (out of contact = the reference), NaN while not imaged, and the tracked pins at the last frame.
// Pins tracked by pin_tracker.hpp; each sample's "pins_tracked" = pins kept in its image.
// max_samples_per_split > 0 keeps only the first rows of each targets.csv (tests).
struct TactipImportOptions {
  PinTrackerOptions tracker;
  int max_samples_per_split = 0;
  int slide_steps = 10;  // frames of the in-contact slide
  // Track against a prior field predicted from each sample's targets (pin_field_prior.hpp), fitted on the
  // calibration split by continuation in depth (first stage: presses up to prior_first_depth_mm tracked
  // without a prior, then steps of prior_step_mm). false: every image tracked without a prior.
  bool use_prior = true;
  // Drop the pins lattice_check.hpp doubts (false: keep every match, e.g. to compare trackers).
  bool lattice_check = true;
  // Store the images (frame 0: the reference, the last frame: the sample's thresholded image; the frames
  // between were not imaged and have none) so the workbench shows them behind the panels.
  bool frames = false;
  // NaN: from the calibration split's depth range (its shallowest quarter, then steps of a sixteenth).
  double prior_first_depth_mm = std::numeric_limits<double>::quiet_NaN();
  double prior_step_mm = std::numeric_limits<double>::quiet_NaN();
  // A sensor description (tactip_sensor.hpp; `import --sensor FILE`): its values replace the defaults and are
  // not identified. Empty: the standard TacTip's defaults, everything the data tell identified.
  std::string sensor_file;
};
ImportReport import_tactip_shear(const std::string& in_dir, const std::string& out_dir,
                                 const TactipImportOptions& options = {});
// The calibration samples the pin prior needs (2 per covariate of its per-pin regression: 66). With fewer,
// no prior is fitted and every deep press loses all its pins (--max-samples 40 wrote 32 of 80 samples with 0 of
// 327 pins tracked).
int tactip_prior_min_calibration_samples();

}  // namespace sb
