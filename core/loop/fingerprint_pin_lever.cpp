// pin_lever's evidence: the outward shift of indented pins at zero penetration (fingerprint_pin_lever.hpp).
#include "core/loop/fingerprint_pin_lever.hpp"

#include <cmath>

namespace sb {

namespace {

constexpr double kPinMinOffsetPx = 1.0;  // a marker this close to the contact centre has no outward direction
// Press frames a sample needs: within one frame the penetration varies across the contact too, and a form error
// at the contact's edge (where h -> 0) reads as a constant there; over a press each marker's own h grows.
constexpr std::size_t kPinMinFrames = 3;

double lever(const Sensor& sensor, const EvidenceSample& s) {
  if (s.marker_depth_m.empty()) return kEvidenceNaN;
  // r_out = a rho + b rho h, least squares: normal equations of the regressors x1 = rho, x2 = rho h.
  double n11 = 0, n12 = 0, n22 = 0, v1 = 0, v2 = 0;
  std::size_t frames = 0;
  for (std::size_t k = 0; k < s.fp.meas_px.size(); ++k) {
    if (!press_frame(s.fp, k) || !moved_frame(s.fp, k)) continue;
    ++frames;
    for (std::size_t j = 0; j < sensor.markers_rest_px.size(); ++j) {
      const double h = s.marker_depth_m[k][j];
      const Vec2 r = residual_px(s.fp, k, j);
      const Vec2 out = sensor.markers_rest_px[j] - s.fp.contact_centre_px[k];
      if (!(h > 0) || !finite(r) || out.norm() < kPinMinOffsetPx) continue;
      const double rho = out.norm(), y = r.dot(out) / rho, x2 = rho * h;
      n11 += rho * rho, n12 += rho * x2, n22 += x2 * x2, v1 += rho * y, v2 += x2 * y;
    }
  }
  if (frames < kPinMinFrames) return kEvidenceNaN;
  const double det = n11 * n22 - n12 * n12;
  // A depth range is needed to tell the constant from the growing part (det ~ 0 at one depth).
  if (!(det > 1e-9 * n11 * n22)) return kEvidenceNaN;
  return (n22 * v1 - n12 * v2) / det;
}

}  // namespace

std::vector<double> lever_shift(const Sensor& sensor, const EvidenceSplit& split) {
  std::vector<double> out;
  for (const auto& s : split.samples) out.push_back(lever(sensor, s));
  return out;
}

EffectEvidence pin_lever_evidence(const Sensor& sensor, const EvidenceSplit& calibration,
                                  const EvidenceSplit& validation, const FittedParam& fitted) {
  EffectEvidence e;
  e.effect = "pin_lever";
  e.looked_at = "the indented markers' outward residual that does not grow with their penetration, in presses";
  e.quantity = "outward shift at first touch";
  e.unit = "px/px";
  e.fitted = fitted("gain");  // >= 0: outward
  const std::string what = "press recorded over at least 3 frames with indented markers (a single image is one depth)";
  e.calibration = split_reading(calibration, lever_shift(sensor, calibration), what);
  e.validation = split_reading(validation, lever_shift(sensor, validation), what);
  conclude_evidence(&e);
  return e;
}

}  // namespace sb
