#pragma once
// The TacTip's camera fitted to its reference's pin rings with the sensor description's values, and how the fit is
// reported.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/sensor/tactip_geometry_fit.hpp"
#include "core/sensor/tactip_sensor.hpp"

namespace sb {

// The camera from the reference's pins (tactip_geometry_fit.hpp). The rings give the principal point, phi0 and
// one function of the ring index whose slope fixes f theta / (a + 1) and whose curvature fixes a: so with the
// skin's ring pitch (the pattern) fixed they give f and D; with f given, theta. R, the pin depth and k1 are what
// the sensor says (they trade with D and with a). The sensor's camera values are set from the fit (source
// kIdentified, unless given). InputError(where) when the pins do not form the rings.
TactipGeometryFit fit_tactip_camera(const std::vector<Vec2>& rest_px, int width_px, int height_px, TactipSensor* sensor,
                                    const std::string& where);

// The fit for the dataset (sensor.tactip.geometry_fit): what was fitted and fixed, the residual and the sigmas.
nlohmann::json tactip_geometry_fit_json(const TactipGeometryFit& fit, const TactipGeometryFitOptions& options);
// The fit in one report line.
std::string tactip_geometry_fit_line(const TactipGeometryFit& fit, const TactipSensor& sensor);

}  // namespace sb
