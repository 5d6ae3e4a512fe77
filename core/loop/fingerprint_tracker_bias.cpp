// tracker_bias's evidence: the motion-independent offset of moving markers (fingerprint_tracker_bias.hpp).
#include "core/loop/fingerprint_tracker_bias.hpp"

#include <cmath>

#include "core/calibration/metrics.hpp"

namespace sb {

std::vector<Vec2> moving_marker_offset_px(const EvidenceSplit& split) {
  std::vector<Vec2> out;
  for (const auto& s : split.samples) {
    Vec2 sum = Vec2::Zero();
    double n = 0;
    for (std::size_t k = 0; k < s.fp.meas_px.size(); ++k) {
      if (!moved_frame(s.fp, k)) continue;
      for (std::size_t j = 0; j < s.fp.meas_px[k].size(); ++j) {
        const Vec2 r = residual_px(s.fp, k, j);
        if (finite(r) && s.fp.meas_px[k][j].norm() > kMotionThresholdPx) sum += r, ++n;
      }
    }
    out.push_back(n > 0 ? Vec2(sum / n) : Vec2(kEvidenceNaN, kEvidenceNaN));
  }
  return out;
}

std::vector<double> component(const std::vector<Vec2>& v, int axis) {
  std::vector<double> out;
  out.reserve(v.size());
  for (const Vec2& x : v) out.push_back(x[axis]);
  return out;
}

int significant_component(const std::vector<Vec2>& calibration) {
  const MeanEstimate x = mean_estimate(component(calibration, 0)), y = mean_estimate(component(calibration, 1));
  const double tx = std::abs(x.mean / x.std_error), ty = std::abs(y.mean / y.std_error);
  return std::isfinite(ty) && !(tx >= ty) ? 1 : 0;
}

EffectEvidence tracker_bias_evidence(const Sensor& /*sensor*/, const EvidenceSplit& calibration,
                                     const EvidenceSplit& validation, const FittedParam& fitted) {
  EffectEvidence e;
  e.effect = "tracker_bias";
  e.looked_at = "the mean residual of the moving markers over samples of every direction";
  const std::vector<Vec2> cal = moving_marker_offset_px(calibration), val = moving_marker_offset_px(validation);
  const int axis = significant_component(cal);
  e.quantity = std::string("offset ") + (axis == 0 ? "u" : "v");
  e.unit = "px";
  e.fitted = fitted(axis == 0 ? "bias_x_px" : "bias_y_px");
  e.calibration = split_reading(calibration, component(cal, axis), "with moving markers");
  e.validation = split_reading(validation, component(val, axis), "with moving markers");
  conclude_evidence(&e);
  return e;
}

}  // namespace sb
