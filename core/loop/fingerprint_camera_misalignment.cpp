// camera_misalignment's evidence: the common turn of the measured field (fingerprint_camera_misalignment.hpp).
#include "core/loop/fingerprint_camera_misalignment.hpp"

#include <cmath>

#include "core/calibration/metrics.hpp"

namespace sb {

std::vector<double> field_turn_rad(const EvidenceSplit& split) {
  std::vector<double> out;
  for (const auto& s : split.samples) {
    double cross = 0, dot = 0;
    for (std::size_t k = 0; k < s.fp.meas_px.size() && k < s.fp.pred_px.size(); ++k) {
      if (!moved_frame(s.fp, k)) continue;
      for (std::size_t j = 0; j < s.fp.meas_px[k].size(); ++j) {
        const Vec2& m = s.fp.meas_px[k][j];
        const Vec2& p = s.fp.pred_px[k][j];
        if (!finite(m) || !finite(p) || m.norm() < kMotionThresholdPx) continue;
        cross += p.x() * m.y() - p.y() * m.x(), dot += p.dot(m);
      }
    }
    out.push_back(dot > 0 ? std::atan2(cross, dot) : kEvidenceNaN);
  }
  return out;
}

EffectEvidence camera_misalignment_evidence(const Sensor& /*sensor*/, const EvidenceSplit& calibration,
                                            const EvidenceSplit& validation, const FittedParam& fitted) {
  EffectEvidence e;
  e.effect = "camera_misalignment";
  e.looked_at = "the angle from the model's displacements to the measured ones, over samples of every motion";
  e.quantity = "camera roll";
  e.unit = "mrad";
  e.unit_scale = 1e3;
  e.fitted = fitted("rotation_rad");
  e.calibration = split_reading(calibration, field_turn_rad(calibration), "with moving markers");
  e.validation = split_reading(validation, field_turn_rad(validation), "with moving markers");
  conclude_evidence(&e);
  return e;
}

}  // namespace sb
