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
#include "core/sensor/sensor.hpp"

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

nlohmann::ordered_json to_json(const TactipSensor& sensor);
// One line per value for a report ("dome_radius_mm 20 (default: ...)").
std::vector<std::string> tactip_sensor_lines(const nlohmann::json& description);

// The gel the sensor description gives: the hemispherical dome (footprint = radius) on a 1 mm base.
GelSpec tactip_gel(const TactipSensor& sensor);
// Which rest pins (1: kept) the sensor can place: each one's ray must meet the pin sphere on the dome (a pin seen
// past its equator sits on the skin's wall, which the spherical-cap gel does not model).
std::vector<char> pins_on_dome(const std::vector<Vec2>& rest_px, const Camera& camera, const GelSpec& gel);

}  // namespace sb
