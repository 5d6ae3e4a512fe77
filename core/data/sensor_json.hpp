#pragma once
// The parts of a sensor description that tsd/1 datasets and scenes share (docs/sensors.md): the camera model
// (orthographic or pinhole), the spherical-cap gel and the pin depth. Bad values throw InputError naming the
// file and the JSON pointer.
#include <nlohmann/json.hpp>
#include <string>

#include "core/sensor/sensor.hpp"

namespace sb {

// Reads camera["model"] ("orthographic" when absent) and, for "pinhole", the required focal_px and
// distance_m (> 0) and the optional k1 (finite). Leaves the orthographic keys to the caller.
void parse_camera_model(const nlohmann::json& camera_json, const std::string& file, const std::string& pointer,
                        Camera* camera);
// Reads a spherical cap's radius_m and footprint_radius_m (> 0, footprint <= radius) into gel and checks
// gel->thickness_m against the cap height. Call after thickness_m is known.
void parse_spherical_cap(const nlohmann::json& gel_json, const std::string& file, const std::string& pointer,
                         GelSpec* gel);
// Checks markers_depth_m (>= 0; < radius_m for a spherical cap) at `pointer`.
double parse_markers_depth(const nlohmann::json& value, const GelSpec& gel, const std::string& file,
                           const std::string& pointer);
// The camera block's model-specific keys for a writer: {"model": "pinhole", "focal_px", "principal_px",
// "distance_m", "k1"}, or the orthographic {"model", "mm_per_px", "principal_px"}.
nlohmann::ordered_json camera_to_json(const Camera& camera);
// Whether a sensor is the one tsd/1 described before pinhole cameras, caps and depths existed (its block is
// written exactly as before).
bool is_classic_sensor(const Camera& camera, const GelSpec& gel);

}  // namespace sb
