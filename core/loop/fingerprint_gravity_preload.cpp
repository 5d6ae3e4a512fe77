// gravity_preload's evidence: the shear at the contact in presses (fingerprint_gravity_preload.hpp).
#include "core/loop/fingerprint_gravity_preload.hpp"

#include <cmath>

#include "core/loop/fingerprint_tracker_bias.hpp"

namespace sb {

namespace {
constexpr double kDefaultWidthM = 0.003;  // the effect's default width, when the answer has none
}

std::vector<Vec2> contact_shear_px(const Sensor& sensor, const EvidenceSplit& split, double width_m) {
  const double w_px = width_m / sensor.camera.metres_per_px();
  std::vector<Vec2> out;
  for (const auto& s : split.samples) {
    Vec2 sum = Vec2::Zero();
    double wsum = 0;
    for (std::size_t k = 0; k < s.fp.meas_px.size(); ++k) {
      if (!press_frame(s.fp, k) || !moved_frame(s.fp, k)) continue;
      for (std::size_t j = 0; j < sensor.markers_rest_px.size(); ++j) {
        const Vec2 r = residual_px(s.fp, k, j);
        if (!finite(r)) continue;
        const double d2 = (sensor.markers_rest_px[j] - s.fp.contact_centre_px[k]).squaredNorm();
        const double w = std::exp(-d2 / (2 * w_px * w_px));
        sum += w * r, wsum += w;
      }
    }
    out.push_back(wsum > 0 ? Vec2(sum / wsum) : Vec2(kEvidenceNaN, kEvidenceNaN));
  }
  return out;
}

EffectEvidence gravity_preload_evidence(const Sensor& sensor, const EvidenceSplit& calibration,
                                        const EvidenceSplit& validation, const FittedParam& fitted) {
  EffectEvidence e;
  e.effect = "gravity_preload";
  e.looked_at = "the mean residual at the contact centre in presses, over samples";
  const double w = fitted("width_m");
  const double width = std::isfinite(w) && w > 0 ? w : kDefaultWidthM;
  const std::vector<Vec2> cal = contact_shear_px(sensor, calibration, width),
                          val = contact_shear_px(sensor, validation, width);
  const int axis = significant_component(cal);
  e.quantity = std::string("shear at the contact ") + (axis == 0 ? "u" : "v");
  e.unit = "px";
  e.fitted = fitted(axis == 0 ? "gx_px" : "gy_px");
  e.calibration = split_reading(calibration, component(cal, axis), "with a press");
  e.validation = split_reading(validation, component(val, axis), "with a press");
  conclude_evidence(&e);
  return e;
}

}  // namespace sb
