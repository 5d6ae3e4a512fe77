#pragma once
// What a TacTip's tracked presses identify of its sensor (docs/sensors.md, "Bringing a new TacTip"): the
// image-from-tool rotation and handedness from the shallow presses' response to the known shear, and the contact
// onset from the depth at which the pins begin to move.
#include <string>
#include <vector>

#include "core/base/numbers.hpp"
#include "core/geometry/pose.hpp"

namespace sb {

// One tracked sample's response to its known slide: the mean displacement of its most displaced pins (the
// stick zone follows the slide), in px, with its press depth and slide in mm.
struct ShearResponse {
  double depth_mm = 0.0;
  Vec2 shear_mm = Vec2::Zero();
  Vec2 response_px = Vec2::Zero();
  double moving_fraction = 0.0;  // tracked pins moved by more than half the stick zone's expected travel
  bool tracked = false;          // any pin tracked
};
// The mean displacement of the 10 % most displaced tracked pins and the count tracked.
Vec2 most_displaced_mean(const std::vector<Vec2>& disp_px, int* tracked = nullptr);

// response = g Rz(a) shear (rotated) or g Rz(a) M shear, M = diag(1, -1) (mirrored), fitted by least squares
// (complex: c = sum m conj(s) / sum |s|^2) on the shallow presses (depth at most the median of the in-contact
// ones) with a slide of at least 30 % of the largest. sigma_rad from the residual variance.
struct ImageFromTool {
  double angle_rad = kNaN, sigma_rad = kNaN, gain_px_per_mm = kNaN;
  bool mirrored = false;
  double rms_px = kNaN, mirrored_rms_px = kNaN, response_rms_px = kNaN;  // rotated fit, mirrored fit, no fit
  int samples = 0;
};
// Only presses deeper than min_depth_mm count (the contact onset, once known: a press short of the touch moves
// nothing whatever its slide). Throws InputError(where) for fewer than 8 usable samples.
ImageFromTool identify_image_from_tool(const std::vector<ShearResponse>& samples, const std::string& where,
                                       double min_depth_mm = -kInf);

// The contact onset: the nominal depth at which the skin first touches. For a flat press on a dome the contact
// disk's area grows linearly with the indentation (pi (2 R (d - d0))), so the fraction of pins that follow a
// slide grows linearly from the onset d0: fitted by least squares on the shallowest in-contact third of the
// presses with a slide of at least half the largest, extrapolated to zero. It is identified (and applied to
// the poses) only when the data hold presses out of contact (no pin moving) below it; otherwise every press
// touches, the data cannot tell where the tool's zero sits, and the default (0: the collection's zero is the
// touch) stands, with the extrapolation reported.
struct ContactOnset {
  double extrapolated_mm = kNaN, sigma_mm = kNaN;
  int out_of_contact = 0;  // presses with no pin moving, below the extrapolated onset
  int in_contact = 0;      // presses the line was fitted on
  double deepest_out_mm = kNaN, shallowest_in_mm = kNaN;
  bool identified = false;
};
ContactOnset identify_contact_onset(const std::vector<ShearResponse>& samples);
// The fraction of the tracked pins displaced by more than threshold_px (0 when none is tracked).
double fraction_moved(const std::vector<Vec2>& disp_px, double threshold_px);

}  // namespace sb
