// Reading and writing the camera model, the spherical-cap gel and the pin depth (sensor_json.hpp).
#include "core/data/sensor_json.hpp"

#include <cmath>

#include "core/data/json_read.hpp"

namespace sb {

using jsonin::child;

void parse_camera_model(const nlohmann::json& cam, const std::string& file, const std::string& ptr, Camera* camera) {
  jsonin::require_object(cam, file, ptr);
  const auto* m = jsonin::find(cam, "model");
  const std::string model = m ? jsonin::string(*m, file, child(ptr, "model")) : "orthographic";
  if (model == "orthographic") {
    camera->model = CameraModel::kOrthographic;
    for (const char* key : {"focal_px", "distance_m", "k1"})
      if (jsonin::find(cam, key)) jsonin::fail(file, child(ptr, key), "only a pinhole camera has this key");
    return;
  }
  if (model != "pinhole")
    jsonin::fail(file, child(ptr, "model"), "unknown camera model '" + model + "' (expected orthographic or pinhole)");
  camera->model = CameraModel::kPinhole;
  camera->focal_px = jsonin::positive_number(jsonin::member(cam, "focal_px", file, ptr), file, child(ptr, "focal_px"));
  camera->distance_m =
      jsonin::positive_number(jsonin::member(cam, "distance_m", file, ptr), file, child(ptr, "distance_m"));
  if (auto* v = jsonin::find(cam, "k1")) camera->k1 = jsonin::finite_number(*v, file, child(ptr, "k1"));
  if (jsonin::find(cam, "mm_per_px"))
    jsonin::fail(file, child(ptr, "mm_per_px"), "a pinhole camera's scale is distance_m / focal_px; drop mm_per_px");
}

void parse_spherical_cap(const nlohmann::json& g, const std::string& file, const std::string& ptr, GelSpec* gel) {
  gel->radius_m = jsonin::positive_number(jsonin::member(g, "radius_m", file, ptr), file, child(ptr, "radius_m"));
  gel->footprint_radius_m = jsonin::positive_number(jsonin::member(g, "footprint_radius_m", file, ptr), file,
                                                    child(ptr, "footprint_radius_m"));
  if (gel->footprint_radius_m > gel->radius_m)
    jsonin::fail(file, child(ptr, "footprint_radius_m"), "must not exceed radius_m (a cap is at most a hemisphere)");
  const double R = gel->radius_m, rho = gel->footprint_radius_m;
  const double cap_height = R - std::sqrt(R * R - rho * rho);
  if (!(gel->thickness_m > cap_height))
    jsonin::fail(file, child(ptr, "thickness_m"),
                 "must exceed the cap height " + std::to_string(cap_height) + " m (radius_m and footprint_radius_m)");
}

double parse_markers_depth(const nlohmann::json& v, const GelSpec& gel, const std::string& file,
                           const std::string& ptr) {
  const double depth = jsonin::finite_number(v, file, ptr);
  if (depth < 0.0) jsonin::fail(file, ptr, "must be >= 0 (metres below the contact surface)");
  if (gel.surface == "spherical_cap" && depth >= gel.radius_m)
    jsonin::fail(file, ptr, "must be smaller than the gel's radius_m");
  return depth;
}

nlohmann::ordered_json camera_to_json(const Camera& camera) {
  if (!camera.pinhole())
    return {{"model", "orthographic"},
            {"mm_per_px", camera.mm_per_px},
            {"principal_px", {camera.principal_px.x(), camera.principal_px.y()}}};
  return {{"model", "pinhole"},
          {"focal_px", camera.focal_px},
          {"principal_px", {camera.principal_px.x(), camera.principal_px.y()}},
          {"distance_m", camera.distance_m},
          {"k1", camera.k1}};
}

bool is_classic_sensor(const Camera& camera, const GelSpec& gel) {
  return !camera.pinhole() && gel.surface != "spherical_cap" && gel.markers_depth_m == 0.0;
}

}  // namespace sb
