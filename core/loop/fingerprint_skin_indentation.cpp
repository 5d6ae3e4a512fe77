// skin_indentation's evidence: indented markers converging on the principal point (fingerprint_skin_indentation.hpp).
#include "core/loop/fingerprint_skin_indentation.hpp"

#include <cmath>

namespace sb {

namespace {

constexpr double kMaxCollinearity = 0.95;  // |corr(h u_pp, h u_cc)| above this: the contact is at the centre
constexpr double kSkinMinOffsetPx = 1.0;   // a marker this close to the centre or the contact has no direction

double convergence(const Sensor& sensor, const EvidenceSample& s) {
  if (s.marker_depth_m.empty()) return kEvidenceNaN;
  double n11 = 0, n12 = 0, n22 = 0, v1 = 0, v2 = 0;
  for (std::size_t k = 0; k < s.fp.meas_px.size(); ++k) {
    if (!press_frame(s.fp, k) || !moved_frame(s.fp, k)) continue;
    for (std::size_t j = 0; j < sensor.markers_rest_px.size(); ++j) {
      const double h = s.marker_depth_m[k][j];
      const Vec2 r = residual_px(s.fp, k, j);
      if (!(h > 0) || !finite(r)) continue;
      const Vec2& m = sensor.markers_rest_px[j];
      const Vec2 to_pp = sensor.camera.principal_px - m, to_cc = s.fp.contact_centre_px[k] - m;
      if (to_pp.norm() < kSkinMinOffsetPx || to_cc.norm() < kSkinMinOffsetPx) continue;
      const Vec2 x1 = h * to_pp.normalized(), x2 = h * to_cc.normalized();
      n11 += x1.squaredNorm(), n12 += x1.dot(x2), n22 += x2.squaredNorm();
      v1 += x1.dot(r), v2 += x2.dot(r);
    }
  }
  const double det = n11 * n22 - n12 * n12;
  if (!(n11 > 0 && n22 > 0) || std::abs(n12) > kMaxCollinearity * std::sqrt(n11 * n22) || !(det > 0))
    return kEvidenceNaN;
  return (n22 * v1 - n12 * v2) / det;
}

}  // namespace

std::vector<double> centre_convergence_px_per_m(const Sensor& sensor, const EvidenceSplit& split) {
  std::vector<double> out;
  for (const auto& s : split.samples) out.push_back(convergence(sensor, s));
  return out;
}

EffectEvidence skin_indentation_evidence(const Sensor& sensor, const EvidenceSplit& calibration,
                                         const EvidenceSplit& validation, const FittedParam& fitted) {
  EffectEvidence e;
  e.effect = "skin_indentation";
  e.looked_at = "the indented markers' residual towards the principal point, apart from towards the contact";
  e.quantity = "convergence towards the image centre";
  e.unit = "px/mm";
  e.unit_scale = 1e-3;
  e.fitted = fitted("gain");  // >= 0: towards the centre
  const std::string what = "press off the image centre with indented markers";
  e.calibration = split_reading(calibration, centre_convergence_px_per_m(sensor, calibration), what);
  e.validation = split_reading(validation, centre_convergence_px_per_m(sensor, validation), what);
  if (!sensor.camera.pinhole())
    e.calibration.missing = e.validation.missing = "an orthographic camera does not see the skin's normal motion";
  conclude_evidence(&e);
  return e;
}

}  // namespace sb
