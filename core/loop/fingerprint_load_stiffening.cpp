// load_stiffening's evidence: the field's gain falling with depth alike near and far (fingerprint_load_stiffening.hpp).
#include "core/loop/fingerprint_load_stiffening.hpp"

#include <algorithm>
#include <cmath>

#include "core/base/format.hpp"

namespace sb {

namespace {

constexpr double kNearFraction = 0.5;  // |pred| >= this x the frame's largest: the near part
constexpr double kFarFraction = 0.1;   // down to this: the far part (below, the field is the noise's)
constexpr std::size_t kStiffeningMinFrames = 3;
// The depths must span this fraction of the deepest for a slope (a hold is one depth).
constexpr double kMinDepthSpan = 0.25;

struct Line {
  double sx = 0, sy = 0, sxx = 0, sxy = 0, n = 0;
  void add(double x, double y) { sx += x, sy += y, sxx += x * x, sxy += x * y, ++n; }
  // b / a of y = a + b x (NaN when under-determined).
  double slope_over_intercept(double min_span) const {
    if (n < kStiffeningMinFrames) return kEvidenceNaN;
    const double var = sxx / n - (sx / n) * (sx / n);
    if (!(var > 0) || !(std::sqrt(var) >= min_span)) return kEvidenceNaN;
    const double b = (sxy / n - (sx / n) * (sy / n)) / var;
    const double a = sy / n - b * sx / n;
    return a > 0 ? b / a : kEvidenceNaN;
  }
};

// The gain of meas against pred over the markers with |pred| in [lo, hi) of the frame's largest; NaN when none.
double part_gain(const FingerprintSample& s, std::size_t k, double lo, double hi) {
  const double peak = max_norm_px(s.pred_px[k]);
  double mp = 0, pp = 0;
  for (std::size_t j = 0; j < s.pred_px[k].size(); ++j) {
    const Vec2& p = s.pred_px[k][j];
    const Vec2& m = s.meas_px[k][j];
    if (!finite(p) || !finite(m)) continue;
    const double f = p.norm() / peak;
    if (f < lo || f >= hi) continue;
    mp += m.dot(p), pp += p.squaredNorm();
  }
  return pp > 0 && mp > 0 ? mp / pp : kEvidenceNaN;
}

}  // namespace

DepthGainSlopes depth_gain_slopes(const EvidenceSplit& split) {
  DepthGainSlopes out;
  for (const auto& s : split.samples) {
    Line all, near, far;
    double deepest = 0;
    for (std::size_t k = 0; k < s.fp.meas_px.size(); ++k) {
      if (!press_frame(s.fp, k) || !moved_frame(s.fp, k) || !(s.depth_m[k] > 0)) continue;
      deepest = std::max(deepest, s.depth_m[k]);
      const double ga = part_gain(s.fp, k, kFarFraction, 2.0), gn = part_gain(s.fp, k, kNearFraction, 2.0),
                   gf = part_gain(s.fp, k, kFarFraction, kNearFraction);
      if (std::isfinite(ga)) all.add(s.depth_m[k], 1 / ga);
      if (std::isfinite(gn)) near.add(s.depth_m[k], 1 / gn);
      if (std::isfinite(gf)) far.add(s.depth_m[k], 1 / gf);
    }
    const double span = kMinDepthSpan * deepest / 2;  // the standard deviation of a uniform ramp is range / sqrt 12
    out.all.push_back(all.slope_over_intercept(span));
    out.near.push_back(near.slope_over_intercept(span));
    out.far.push_back(far.slope_over_intercept(span));
  }
  return out;
}

namespace {

SplitReading load_stiffening_reading(const EvidenceSplit& split) {
  const DepthGainSlopes g = depth_gain_slopes(split);
  const std::string what = "press over a depth range";
  SplitReading r = reading_of(g.all, what);
  r.noise_px = split.noise_px;
  const SplitReading n = reading_of(g.near, what), f = reading_of(g.far, what);
  r.detail = "near the contact " + format_number(n.estimate, "%.3g", "nan") + " ± " +
             format_number(n.std_error, "%.2g", "nan") + " /m, away from it " +
             format_number(f.estimate, "%.3g", "nan") + " ± " + format_number(f.std_error, "%.2g", "nan") + " /m";
  if (!r.missing.empty()) return r;
  const EvidenceRules rules;
  const double a = n.estimate, b = f.estimate;
  const bool agree = a * b > 0 &&
                     std::max(std::abs(a), std::abs(b)) <= rules.agreement * std::min(std::abs(a), std::abs(b));
  if (!agree)
    r.missing = "the gain does not fall alike near the contact and away from it (" + r.detail +
                "): the field changes shape with depth, a contact-form error, not a stiffer gel";
  return r;
}

}  // namespace

EffectEvidence load_stiffening_evidence(const Sensor& /*sensor*/, const EvidenceSplit& calibration,
                                        const EvidenceSplit& validation, const FittedParam& fitted) {
  EffectEvidence e;
  e.effect = "load_stiffening";
  e.looked_at = "the field's gain against depth in presses, near the contact and away from it";
  e.quantity = "stiffening beta";
  e.unit = "/m";
  e.fitted = fitted("beta_per_m");
  e.calibration = load_stiffening_reading(calibration);
  e.validation = load_stiffening_reading(validation);
  conclude_evidence(&e);
  return e;
}

}  // namespace sb
