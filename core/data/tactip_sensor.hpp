#pragma once
// A TacTip's sensor description read from a file (`import --sensor FILE`, or a dataset's own description); the
// description itself, its defaults and its JSON form: core/sensor/tactip_sensor.hpp.
#include <nlohmann/json.hpp>
#include <string>

#include "core/sensor/tactip_sensor.hpp"

namespace sb {

// The values a --sensor FILE gives, over `into` (source kGiven): a JSON object whose "values" (or the object
// itself) maps keys of TactipSensor::values() to a number or to {"value": number, ...} (the dataset's own
// description reads back). Unknown keys and bad values are InputErrors naming the file and the JSON pointer.
void read_tactip_sensor_file(const std::string& path, TactipSensor* into);
// The same from parsed JSON (`file` names it in errors).
void apply_tactip_sensor_json(const nlohmann::json& j, const std::string& file, TactipSensor* into);

}  // namespace sb
