// The TacTip's camera fitted to its reference's pin rings (tactip_sensor_camera.hpp).
#include "core/sensor/tactip_sensor_camera.hpp"

#include <cmath>

#include "core/base/format.hpp"

namespace sb {

namespace {

constexpr double kDeg = M_PI / 180.0;

// The pinhole camera the ring fit starts from: with the ring pitch theta fixed (the skin's pattern), ring 1's
// image radius rho_1 = f sin theta / (a + cos theta), a = (D - R) / r_p, started at a = 2 (the camera a dome's
// diameter below the apex; the fit moves it); with the focal length given, the distance such that the pin
// sphere's equator is seen at the image's half-width.
Camera tactip_start_camera(int width_px, int height_px, const TactipSensor& s, double ring1_px) {
  Camera c;
  c.model = CameraModel::kPinhole;
  c.width_px = width_px;
  c.height_px = height_px;
  c.principal_px = Vec2((width_px - 1) / 2.0, (height_px - 1) / 2.0);
  c.k1 = s.k1.value;
  const double R = s.dome_radius_mm.value * 1e-3, rp = R - s.pin_depth_mm.value * 1e-3;
  const double theta = s.ring_pitch_deg.value * kDeg;
  if (s.focal_px.source == SensorValueSource::kGiven) {
    c.focal_px = s.focal_px.value;
    c.distance_m = R + c.focal_px * rp / (0.5 * width_px);
  } else {
    constexpr double kStartA = 2.0;
    c.focal_px = ring1_px * (kStartA + std::cos(theta)) / std::sin(theta);
    c.distance_m = R + kStartA * rp;
  }
  if (s.distance_mm.source == SensorValueSource::kGiven) c.distance_m = s.distance_mm.value * 1e-3;
  return c;
}

}  // namespace

// The camera from the reference's pins (tactip_geometry_fit.hpp). The rings give the principal point, phi0 and
// one function of the ring index whose slope fixes f theta / (a + 1) and whose curvature fixes a: so with the
// skin's ring pitch (the pattern) fixed they give f and D; with f given, theta. R, the pin depth and k1 are what
// the sensor says (they trade with D and with a). The sensor's camera values are set from the fit.
TactipGeometryFit fit_tactip_camera(const std::vector<Vec2>& rest_px, int width_px, int height_px, TactipSensor* s,
                                    const std::string& where) {
  const TactipRings rings = assign_tactip_rings(rest_px, where);
  TactipGeometryFitOptions o;
  o.dome_radius_m = s->dome_radius_mm.value * 1e-3;
  o.pin_depth_m = s->pin_depth_mm.value * 1e-3;
  o.initial = tactip_start_camera(width_px, height_px, *s, rings.ring_radius_px.at(1));
  const bool focal_given = s->focal_px.source == SensorValueSource::kGiven;
  const bool pitch_given = s->ring_pitch_deg.source == SensorValueSource::kGiven;
  o.fit_focal = !focal_given;
  o.fit_ring_pitch = focal_given && !pitch_given;
  o.ring_pitch_rad = s->ring_pitch_deg.value * kDeg;
  o.fit_distance = s->distance_mm.source != SensorValueSource::kGiven;
  o.fit_k1 = false;
  TactipGeometryFit g = fit_tactip_geometry(rest_px, o, where);
  const std::string how = "fitted to the reference's " + std::to_string(g.pins_used) + " pins in " +
                          std::to_string(g.rings.ring_radius_px.size() - 1) + " rings (RMS " +
                          format_number(g.rms_px, "%.3f") + " px)";
  auto set = [&](SensorValue& v, double value, double sigma, bool fitted) {
    if (!fitted) return;
    v = {value, sigma, SensorValueSource::kIdentified, how};
  };
  set(s->focal_px, g.camera.focal_px, g.sigma_focal_px, o.fit_focal);
  set(s->distance_mm, g.camera.distance_m * 1e3, g.sigma_distance_m * 1e3, o.fit_distance);
  set(s->ring_pitch_deg, g.ring_pitch_rad / kDeg, g.sigma_pitch_rad / kDeg, o.fit_ring_pitch);
  if (s->principal_u_px.source != SensorValueSource::kGiven)
    set(s->principal_u_px, g.camera.principal_px.x(), g.sigma_principal_px.x(), true);
  if (s->principal_v_px.source != SensorValueSource::kGiven)
    set(s->principal_v_px, g.camera.principal_px.y(), g.sigma_principal_px.y(), true);
  else
    g.camera.principal_px = Vec2(s->principal_u_px.value, s->principal_v_px.value);
  return g;
}

nlohmann::json tactip_geometry_fit_json(const TactipGeometryFit& g, const TactipGeometryFitOptions& o) {
  constexpr double kRadToDeg = 180.0 / M_PI;
  std::vector<std::string> fitted{"principal_px", "azimuth_deg"}, fixed{"k1", "gel.radius_m", "markers_depth_m"};
  (o.fit_distance ? fitted : fixed).push_back("distance_m");
  (o.fit_focal ? fitted : fixed).push_back("focal_px");
  (o.fit_ring_pitch ? fitted : fixed).push_back("ring_pitch_deg");
  return {{"fitted", fitted},
          {"fixed", fixed},
          {"pattern", "apex pin + rings i = 1.. of 6 i pins at polar angle i * ring_pitch on the pin sphere"},
          {"rings", int(g.rings.ring_radius_px.size()) - 1},
          {"pins_used", g.pins_used},
          {"rms_px", g.rms_px},
          {"max_px", g.max_px},
          {"ring_pitch_deg", g.ring_pitch_rad * kRadToDeg},
          {"outer_ring_polar_deg", g.outer_ring_polar_rad() * kRadToDeg},
          {"azimuth_deg", g.azimuth_rad * kRadToDeg},
          {"sigma_principal_px", {g.sigma_principal_px.x(), g.sigma_principal_px.y()}},
          {"sigma_focal_px", g.sigma_focal_px},
          {"sigma_distance_m", g.sigma_distance_m},
          {"sigma_ring_pitch_deg", g.sigma_pitch_rad * kRadToDeg}};
}

std::string tactip_geometry_fit_line(const TactipGeometryFit& g, const TactipSensor& s) {
  const Camera& c = g.camera;
  auto pm = [](double v, double sigma, const char* fmt) {
    return format_number(v, fmt) + (std::isfinite(sigma) ? " +- " + format_number(sigma, "%.2g") : std::string());
  };
  return "geometry fit on the reference's pin rings: " + std::to_string(g.pins_used) + " pins in " +
         std::to_string(g.rings.ring_radius_px.size() - 1) + " rings, principal point (" +
         format_number(c.principal_px.x(), "%.2f") + ", " + format_number(c.principal_px.y(), "%.2f") + ") +- " +
         format_number(g.sigma_principal_px.x(), "%.2f") + " px, focal " + pm(c.focal_px, g.sigma_focal_px, "%.1f") +
         " px (" + to_string(s.focal_px.source) + "), distance " +
         pm(c.distance_m * 1e3, g.sigma_distance_m * 1e3, "%.2f") + " mm, ring pitch " +
         pm(g.ring_pitch_rad / kDeg, g.sigma_pitch_rad / kDeg, "%.3f") + " deg (" + to_string(s.ring_pitch_deg.source) +
         "; outer ring at " + format_number(g.outer_ring_polar_rad() / kDeg, "%.1f") + " deg); k1 " +
         format_number(c.k1, "%.0f") + ", R " + format_number(s.dome_radius_mm.value, "%.4g") + " mm, pin depth " +
         format_number(s.pin_depth_mm.value, "%.4g") + " mm (" + to_string(s.dome_radius_mm.source) +
         "); residual RMS " + format_number(g.rms_px, "%.3f") + " px, max " + format_number(g.max_px, "%.2f") + " px";
}

}  // namespace sb
