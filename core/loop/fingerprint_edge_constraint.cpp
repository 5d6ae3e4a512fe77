// edge_constraint's evidence: the gain at the pad's sides against its interior (fingerprint_edge_constraint.hpp).
#include "core/loop/fingerprint_edge_constraint.hpp"

#include <algorithm>
#include <cmath>

namespace sb {

namespace {
constexpr double kDefaultLengthM = 0.002;  // the effect's default boundary length, when the answer has none
}

std::vector<double> edge_hold_back(const Sensor& sensor, const EvidenceSplit& split, double length_m) {
  // The effect's own profile w = exp(-dist / l) per marker, and the markers split at its median: the outer half.
  const Vec2 half = 0.5 * sensor.gel.size_m;
  std::vector<double> w;
  for (const Vec3& p : sensor.p_EM)
    w.push_back(std::exp(-std::max(0.0, std::min(half.x() - std::abs(p.x()), half.y() - std::abs(p.y()))) / length_m));
  std::vector<double> sorted = w;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
  const double median = sorted.empty() ? 0.0 : sorted[sorted.size() / 2];
  std::vector<double> out;
  for (const auto& s : split.samples) {
    // Per half: sum meas.pred, sum |pred|^2 and sum w |pred|^2.
    double mp[2] = {0, 0}, pp[2] = {0, 0}, wpp[2] = {0, 0};
    for (std::size_t k = 0; k < s.fp.meas_px.size(); ++k) {
      if (!moved_frame(s.fp, k)) continue;
      for (std::size_t j = 0; j < w.size() && j < s.fp.pred_px[k].size(); ++j) {
        const Vec2& m = s.fp.meas_px[k][j];
        const Vec2& p = s.fp.pred_px[k][j];
        if (!finite(m) || !finite(p)) continue;
        const int outer = w[j] > median ? 1 : 0;
        mp[outer] += m.dot(p), pp[outer] += p.squaredNorm(), wpp[outer] += w[j] * p.squaredNorm();
      }
    }
    if (!(pp[0] > 0 && pp[1] > 0 && mp[0] > 0)) {
      out.push_back(kEvidenceNaN);
      continue;
    }
    // g = g0 (1 - s w): the gains' ratio rho = (1 - s w_outer) / (1 - s w_inner) gives s.
    const double rho = (mp[1] / pp[1]) / (mp[0] / pp[0]);
    const double w_out = wpp[1] / pp[1], w_in = wpp[0] / pp[0];
    const double den = w_out - rho * w_in;
    out.push_back(std::abs(den) > 1e-12 ? (1 - rho) / den : kEvidenceNaN);
  }
  return out;
}

EffectEvidence edge_constraint_evidence(const Sensor& sensor, const EvidenceSplit& calibration,
                                        const EvidenceSplit& validation, const FittedParam& fitted) {
  EffectEvidence e;
  e.effect = "edge_constraint";
  e.looked_at = "the field's gain within a boundary length of the pad's sides against its interior";
  e.quantity = "strength of the hold-back at the sides";
  e.unit = "";
  e.fitted = fitted("strength");
  const double l = fitted("length_m");
  const double length = std::isfinite(l) && l > 0 ? l : kDefaultLengthM;
  const std::string what = "with field both at the sides and inside";
  e.calibration = split_reading(calibration, edge_hold_back(sensor, calibration, length), what);
  e.validation = split_reading(validation, edge_hold_back(sensor, validation, length), what);
  conclude_evidence(&e);
  return e;
}

}  // namespace sb
