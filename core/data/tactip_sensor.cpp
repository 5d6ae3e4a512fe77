// A TacTip's sensor description read from a file (tactip_sensor.hpp).
#include "core/data/tactip_sensor.hpp"

#include <algorithm>

#include "core/data/json_read.hpp"

namespace sb {

void apply_tactip_sensor_json(const nlohmann::json& j, const std::string& file, TactipSensor* into) {
  jsonin::require_object(j, file, "");
  const nlohmann::json* values = jsonin::find(j, "values");
  const std::string base = values ? "/values" : "";
  const nlohmann::json& obj = values ? *values : j;
  jsonin::require_object(obj, file, base);
  auto keys = into->values();
  for (auto it = obj.begin(); it != obj.end(); ++it) {
    const std::string ptr = jsonin::child(base, it.key());
    if (!values && (it.key() == "type" || it.key() == "crop_px" || it.key() == "reference" ||
                    it.key().rfind("onset_extrapolated", 0) == 0))
      continue;
    const auto k = std::find_if(keys.begin(), keys.end(), [&](const auto& p) { return p.first == it.key(); });
    if (k == keys.end()) {
      std::string known;
      for (const auto& p : keys) known += (known.empty() ? "" : ", ") + p.first;
      jsonin::fail(file, ptr, "unknown sensor value (known: " + known + ")");
    }
    const nlohmann::json* v = &it.value();
    std::string vptr = ptr;
    if (v->is_object()) {
      v = &jsonin::member(*v, "value", file, ptr);
      vptr = jsonin::child(ptr, "value");
    }
    if (v->is_null()) continue;  // not known: identified or defaulted as without the file
    SensorValue& out = *k->second;
    out.value = v->is_boolean() ? double(v->get<bool>()) : jsonin::finite_number(*v, file, vptr);
    out.sigma = kNaN;
    out.source = SensorValueSource::kGiven;
    out.how = "given in " + file;
  }
  if (into->dome_radius_mm.value <= 0) jsonin::fail(file, jsonin::child(base, "dome_radius_mm"), "must be > 0");
  if (!(into->pin_depth_mm.value >= 0 && into->pin_depth_mm.value < into->dome_radius_mm.value))
    jsonin::fail(file, jsonin::child(base, "pin_depth_mm"), "must be >= 0 and below dome_radius_mm");
  for (const char* key : {"ring_pitch_deg", "focal_px", "distance_mm"}) {
    const auto k = std::find_if(keys.begin(), keys.end(), [&](const auto& p) { return p.first == key; });
    if (k->second->source == SensorValueSource::kGiven && !(k->second->value > 0))
      jsonin::fail(file, jsonin::child(base, key), "must be > 0");
  }
}

void read_tactip_sensor_file(const std::string& path, TactipSensor* into) {
  apply_tactip_sensor_json(jsonin::load_file(path), path, into);
}

}  // namespace sb
