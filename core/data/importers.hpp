#pragma once
// Converters from the raw recordings in <data>/raw/ into tsd/1 (FORMAT.md). Each records in `provenance`
// what was done: source files, scale, grid, axis convention, and for unknown poses how they were estimated.
//
// Axis convention: the sensor camera looks along +z_E from inside the gel, so image u (right) and v (down)
// are already x_E and y_E of a right-handed E with +z out of the gel: no mirroring is applied.
#include <limits>
#include <string>
#include <vector>

#include "core/data/tsd_out.hpp"
#include "core/tracking/pin_tracker.hpp"
#include "core/tracking/tracker.hpp"

namespace sb {

struct ImportReport {
  std::vector<std::string> datasets;  // directories written
  std::vector<std::string> lines;     // one human-readable line per recording (lost fraction, warnings)
};

// Wraps one tracked recording as a tsd/1 dataset: motion `free`, pose_known false, placeholder identity
// poses (said so in provenance), markers_rest_px from the tracker's rest estimate.
TsdDatasetOut dataset_from_track(const TrackResult& track, const std::string& name, const std::string& sample_id,
                                 double dt_s, double mm_per_px, const std::string& source_note);

// raw/gsrobotics_tracking: one dataset per video (video_N.avi, mini_example.avi) under out_dir/<stem>/,
// because tsd/1 has one markers_rest_px per dataset and each recording has its own rest.
// keep_frames: also store the decoded video frames (frames/NNNNNN.png) so the workbench shows the real image.
ImportReport import_gsrobotics(const std::string& in_dir, const std::string& out_dir, const TrackerOptions& opts,
                               double mm_per_px, bool keep_frames = false);
// raw/incipient_slip: one dataset per clip under out_dir/<experiment>_<camera>/, sample field
// "slip_label" = true when the experiment folder holds slip.txt.
ImportReport import_incipient_slip(const std::string& in_dir, const std::string& out_dir, const TrackerOptions& opts,
                                   double mm_per_px, bool keep_frames = false);
// raw/fots_marker_calib: one dataset, samples "press" and "shear" (frame 0 rest, frame 1 the CSV field),
// indenter pose estimated from the marker field (see SphereContactEstimate).
ImportReport import_fots(const std::string& in_dir, const std::string& out_dir);
// raw/feats: one dataset, sample "cuboid_contact" with frames [nocontact, contact] and tracked markers.
ImportReport import_feats(const std::string& in_dir, const std::string& out_dir);

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
// no prior is fitted and every deep press loses all its pins (issue 34: --max-samples 40 wrote 32 of 80
// samples with 0 of 327 pins tracked).
int tactip_prior_min_calibration_samples();

// The flat surface's pose path X_SI in the tool frame S (the importer turns it into E) for one TacTip sample (SI
// units): depth d, tilt (rx, ry) and twist w in radians, shear (sx, sy) in metres. See importers.cpp for the frame
// conventions. above_m: the clearance of the first ("above") frame.
std::vector<Pose> tactip_pose_path(double depth_m, double rx, double ry, double sx_m, double sy_m, double twist,
                                   int slide_steps, double above_m);

// Sphere contact from a marker displacement field (pixels): far-field drift = median displacement of all
// markers, removed first; centre = |d|-weighted centroid of the markers above half the peak |d|; contact
// radius a = radius of the peak mean radial displacement (for a sphere pressed into a layer the surface
// radial displacement peaks near the contact edge), uncertainty half a pitch; tangential travel = mean
// displacement of the markers inside a (the radial parts cancel by symmetry).
struct SphereContactEstimate {
  Vec2 centre_px = Vec2::Zero();
  Vec2 drift_px = Vec2::Zero();
  double a_px = 0, a_sigma_px = 0;
  Vec2 travel_px = Vec2::Zero();
  double travel_sigma_px = 0;
  int markers_inside = 0;
};
SphereContactEstimate estimate_sphere_contact(const std::vector<Vec2>& rest_px, const std::vector<Vec2>& disp_px,
                                              double pitch_px);
// The same with a given centre and contact radius (drift removed, travel = mean displacement inside a).
SphereContactEstimate estimate_sphere_contact_with_radius(const std::vector<Vec2>& rest_px,
                                                          const std::vector<Vec2>& disp_px, const Vec2& centre_px,
                                                          double a_px, double a_sigma_px);
// Spherical-cap depth d = R - sqrt(R^2 - a^2); NaN when a > R.
double sphere_depth_from_contact_radius(double R, double a);

// Writes a closed UV sphere of radius r (metres) centred at the origin, outward normals, as OBJ text.
std::string sphere_obj(double radius_m, int slices = 32, int stacks = 16);

}  // namespace sb
