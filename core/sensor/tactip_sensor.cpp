// A TacTip's sensor description: its values with their sources, its defaults and the gel it gives
// (tactip_sensor.hpp).
#include "core/sensor/tactip_sensor.hpp"

#include <cmath>

#include "core/base/error.hpp"
#include "core/base/format.hpp"
#include "core/sensor/sensor.hpp"

namespace sb {

std::string to_string(SensorValueSource source) {
  switch (source) {
    case SensorValueSource::kIdentified: return "identified";
    case SensorValueSource::kGiven: return "given";
    case SensorValueSource::kDefault: break;
  }
  return "default";
}

namespace {
// The keys and values of a (const or not) TactipSensor, in the file's order.
template <typename Sensor, typename Value>
std::vector<std::pair<std::string, Value*>> value_list(Sensor& s) {
  return {{"dome_radius_mm", &s.dome_radius_mm},
          {"pin_depth_mm", &s.pin_depth_mm},
          {"ring_pitch_deg", &s.ring_pitch_deg},
          {"focal_px", &s.focal_px},
          {"distance_mm", &s.distance_mm},
          {"k1", &s.k1},
          {"principal_u_px", &s.principal_u_px},
          {"principal_v_px", &s.principal_v_px},
          {"image_from_tool_deg", &s.image_from_tool_deg},
          {"mirrored", &s.mirrored},
          {"contact_onset_mm", &s.contact_onset_mm}};
}
}  // namespace

std::vector<std::pair<std::string, SensorValue*>> TactipSensor::values() {
  return value_list<TactipSensor, SensorValue>(*this);
}

std::vector<std::pair<std::string, const SensorValue*>> TactipSensor::values() const {
  return value_list<const TactipSensor, const SensorValue>(*this);
}

TactipSensor tactip_standard_defaults() {
  TactipSensor s;
  s.dome_radius_mm = {20.0, kNaN, SensorValueSource::kDefault,
                      "the standard TacTip's 40 mm hemispherical tip (Lepora group, J. Robot. Biomim. 2017, fig. 2); "
                      "the rings cannot tell it from the camera distance"};
  s.pin_depth_mm = {3.0, kNaN, SensorValueSource::kDefault,
                    "assumed: 1 mm skin + about 2 mm pins; only moves the fitted distance"};
  s.ring_pitch_deg = {8.0, kNaN, SensorValueSource::kDefault,
                      "the printed pin pattern: 10 rings of 6 i pins, 8 deg apart in polar angle (to 80 deg); the "
                      "rings fix only its product with the focal length"};
  s.focal_px = {kNaN, kNaN, SensorValueSource::kDefault, "fitted to the reference's pin rings"};
  s.distance_mm = {kNaN, kNaN, SensorValueSource::kDefault, "fitted to the reference's pin rings"};
  s.k1 = {0.0, kNaN, SensorValueSource::kDefault, "no distortion: it trades with the distance at third order"};
  s.principal_u_px = {kNaN, kNaN, SensorValueSource::kDefault, "fitted to the reference's pin rings"};
  s.principal_v_px = {kNaN, kNaN, SensorValueSource::kDefault, "fitted to the reference's pin rings"};
  s.image_from_tool_deg = {kNaN, kNaN, SensorValueSource::kDefault, "fitted to the shallow presses' slide"};
  s.mirrored = {0.0, kNaN, SensorValueSource::kDefault, "the camera sees the tool axes rotated, not mirrored"};
  s.contact_onset_mm = {0.0, kNaN, SensorValueSource::kDefault, "the collection's zero depth is the touch"};
  return s;
}

nlohmann::ordered_json to_json(const TactipSensor& s) {
  nlohmann::ordered_json values = nlohmann::ordered_json::object();
  for (const auto& [key, v] : s.values()) {
    nlohmann::ordered_json e;
    e["value"] = std::isfinite(v->value) ? nlohmann::ordered_json(v->value) : nlohmann::ordered_json();
    e["sigma"] = std::isfinite(v->sigma) ? nlohmann::ordered_json(v->sigma) : nlohmann::ordered_json();
    e["source"] = to_string(v->source);
    e["how"] = v->how;
    values[key] = e;
  }
  auto number = [](double v) { return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(); };
  return {{"type", s.type},
          {"crop_px", {s.width_px, s.height_px}},
          {"reference", s.reference},
          {"values", values},
          {"onset_extrapolated_mm", number(s.onset_extrapolated_mm)},
          {"onset_extrapolated_sigma_mm", number(s.onset_extrapolated_sigma_mm)}};
}

std::vector<std::string> tactip_sensor_lines(const nlohmann::json& d) {
  std::vector<std::string> out;
  if (!d.is_object() || !d.contains("values")) return out;
  if (d.contains("reference")) out.push_back("reference: " + d.at("reference").get<std::string>());
  for (auto it = d.at("values").begin(); it != d.at("values").end(); ++it) {
    const auto& e = it.value();
    std::string line = it.key() + " ";
    line += e.value("value", nlohmann::json()).is_number() ? format_number(e.at("value").get<double>(), "%.4g") : "-";
    if (e.value("sigma", nlohmann::json()).is_number())
      line += " +- " + format_number(e.at("sigma").get<double>(), "%.2g");
    line += " (" + e.value("source", std::string("?")) + ": " + e.value("how", std::string()) + ")";
    out.push_back(line);
  }
  return out;
}

// The gel the sensor description gives: the hemispherical dome (footprint = radius) on a 1 mm base.
GelSpec tactip_gel(const TactipSensor& s) {
  GelSpec gel;
  const double R = s.dome_radius_mm.value * 1e-3;
  gel.surface = "spherical_cap";
  gel.radius_m = R;
  gel.footprint_radius_m = R;
  gel.size_m = Vec2(2 * R, 2 * R);
  gel.thickness_m = R + 0.001;
  gel.markers_depth_m = s.pin_depth_mm.value * 1e-3;
  return gel;
}

// Which rest pins the sensor can place: each one's ray must meet the pin sphere on the dome (a pin seen past its
// equator sits on the skin's wall, which the spherical-cap gel does not model). Such pins are left out of the
// dataset (counted in the report), so that every evaluation and fit builds the sensor.
std::vector<char> pins_on_dome(const std::vector<Vec2>& rest_px, const Camera& camera, const GelSpec& gel) {
  std::vector<char> keep(rest_px.size(), 1);
  for (std::size_t i = 0; i < rest_px.size(); ++i) {
    try {
      (void)make_sensor(camera, gel, {rest_px[i]});
    } catch (const InputError&) {
      keep[i] = 0;
    }
  }
  return keep;
}

}  // namespace sb
