#pragma once
// One TacTip's sensor description (docs/sensors.md, "Bringing a new TacTip"): every value the import needs
// about the sensor instance, each with where it came from. The import identifies from the data what the data
// can tell (the camera from the reference's pin rings, the image-from-tool rotation and handedness from the
// shallow presses' response to the known shear, the contact onset from the depth at which the pins begin to
// move) and takes a documented default for the rest; `import --sensor FILE` gives values instead. Written into
// the dataset (sensor.tactip.description of dataset.json) and printed by `check`.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/base/numbers.hpp"
#include "core/sensor/camera.hpp"

namespace sb {

// Where a value came from.
enum class SensorValueSource { kIdentified, kDefault, kGiven };
std::string to_string(SensorValueSource source);

struct SensorValue {
  double value = kNaN;
  double sigma = kNaN;  // one standard deviation; NaN when the source gives none
  SensorValueSource source = SensorValueSource::kDefault;
  std::string how;  // one line: what it was identified from, or why the default
};

// The values, in the units their keys name (mm, deg, px: what a user reads off a datasheet).
struct TactipSensor {
  std::string type = "TacTip (standard: 331 pins in 10 rings)";
  int width_px = 0, height_px = 0;  // the crop, from the reference image
  std::string reference;            // the rest image and why it is the rest
  SensorValue dome_radius_mm, pin_depth_mm, ring_pitch_deg;
  SensorValue focal_px, distance_mm, k1, principal_u_px, principal_v_px;
  SensorValue image_from_tool_deg, mirrored, contact_onset_mm;
  // The onset's line extrapolated to zero, also when the data cannot confirm it (no press out of contact).
  double onset_extrapolated_mm = kNaN, onset_extrapolated_sigma_mm = kNaN;

  // The keys of the file, in order, with the value each names.
  std::vector<std::pair<std::string, SensorValue*>> values();
  std::vector<std::pair<std::string, const SensorValue*>> values() const;
};

// The standard TacTip's defaults for what one set cannot tell (docs/sensors.md has each one's source): the skin
// (dome radius, pin depth below the contact surface, the pin pattern's ring pitch), no distortion, the tool's
// zero at the touch, not mirrored. The camera, the rotation and the onset start unset (NaN): the import
// identifies them.
TactipSensor tactip_standard_defaults();

// The values a --sensor FILE gives, over `into` (source kGiven): a JSON object whose "values" (or the object
// itself) maps keys of TactipSensor::values() to a number or to {"value": number, ...} (the dataset's own
// description reads back). Unknown keys and bad values are InputErrors naming the file and the JSON pointer.
void read_tactip_sensor_file(const std::string& path, TactipSensor* into);
// The same from parsed JSON (`file` names it in errors).
void apply_tactip_sensor_json(const nlohmann::json& j, const std::string& file, TactipSensor* into);

nlohmann::ordered_json to_json(const TactipSensor& sensor);
// One line per value for a report ("dome_radius_mm 20 (default: ...)").
std::vector<std::string> tactip_sensor_lines(const nlohmann::json& description);

// ---- identification from the data -------------------------------------------------------------------------
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
