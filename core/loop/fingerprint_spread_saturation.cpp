// spread_saturation's evidence: the near field's gain falling with depth faster than the far field's
// (fingerprint_spread_saturation.hpp).
#include "core/loop/fingerprint_spread_saturation.hpp"

#include <cmath>

#include "core/loop/fingerprint_load_stiffening.hpp"

namespace sb {

namespace {

SplitReading spread_saturation_reading(const EvidenceSplit& split) {
  const DepthGainSlopes g = depth_gain_slopes(split);
  std::vector<double> diff;
  for (std::size_t i = 0; i < g.near.size(); ++i) diff.push_back(g.near[i] - g.far[i]);
  SplitReading r = reading_of(diff, "press over a depth range with both parts of the field read");
  r.noise_px = split.noise_px;
  return r;
}

}  // namespace

EffectEvidence spread_saturation_evidence(const Sensor& /*sensor*/, const EvidenceSplit& calibration,
                                          const EvidenceSplit& validation, const FittedParam& fitted) {
  EffectEvidence e;
  e.effect = "spread_saturation";
  e.looked_at = "how much faster the field's gain falls with depth near the contact than away from it, in presses";
  e.quantity = "beta near - beta far";
  e.unit = "/m";
  // The fit's sign: a saturating spread (gain > 0) lowers the near field at depth (a positive difference).
  const double gain = fitted("gain_px");
  e.fitted = std::isfinite(gain) ? gain : kEvidenceNaN;
  e.calibration = spread_saturation_reading(calibration);
  e.validation = spread_saturation_reading(validation);
  conclude_evidence(&e);
  return e;
}

}  // namespace sb
