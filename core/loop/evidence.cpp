// What the evidence readers share (evidence.hpp).
#include "core/loop/evidence.hpp"

#include <algorithm>
#include <cmath>

#include "core/base/format.hpp"
#include "core/calibration/metrics.hpp"

namespace sb {

namespace {

std::string evidence_num(double v) { return format_number(v, "%.3g", "nan"); }

std::string describe(const SplitReading& r, const EffectEvidence& e) {
  return evidence_num(r.estimate * e.unit_scale) + " ± " + evidence_num(r.std_error * e.unit_scale) + " " + e.unit +
         " (" + evidence_num(r.samples) + " samples" + (r.detail.empty() ? "" : "; " + r.detail) + ")";
}

// Why one split does not show the effect ("" when it does).
std::string split_missing(const SplitReading& r, const EvidenceRules& rules) {
  if (!r.missing.empty()) return r.missing;
  if (!std::isfinite(r.estimate) || !std::isfinite(r.std_error)) return "no reading";
  if (!(std::abs(r.estimate) > rules.sigmas * r.std_error))
    return "within " + evidence_num(rules.sigmas) + " standard errors of 0";
  return "";
}

}  // namespace

MeanEstimate mean_estimate(const std::vector<double>& values) {
  MeanEstimate m;
  double sum = 0;
  for (double v : values)
    if (std::isfinite(v)) sum += v, ++m.n;
  if (m.n == 0) return m;
  m.mean = sum / m.n;
  if (m.n < 2) return m;
  double ss = 0;
  for (double v : values)
    if (std::isfinite(v)) ss += (v - m.mean) * (v - m.mean);
  m.std_error = std::sqrt(ss / (m.n - 1) / m.n);
  return m;
}

SplitReading reading_of(const std::vector<double>& per_sample, const std::string& what, const EvidenceRules& rules) {
  SplitReading r;
  const MeanEstimate m = mean_estimate(per_sample);
  r.estimate = m.mean;
  r.std_error = m.std_error;
  r.samples = m.n;
  if (m.n < rules.min_samples)
    r.missing = "only " + evidence_num(m.n) + " samples " + what + " (< " + evidence_num(rules.min_samples) + ")";
  return r;
}

SplitReading split_reading(const EvidenceSplit& split, const std::vector<double>& per_sample, const std::string& what) {
  SplitReading r = reading_of(per_sample, what);
  r.noise_px = split.noise_px;
  return r;
}

void conclude_evidence(EffectEvidence* e, const EvidenceRules& rules) {
  const std::string cal = split_missing(e->calibration, rules), val = split_missing(e->validation, rules);
  const std::string read = "calibration " + describe(e->calibration, *e) + ", validation " +
                           describe(e->validation, *e);
  std::string why;
  if (!cal.empty() || !val.empty()) {
    if (!cal.empty()) why = "calibration: " + cal;
    if (!val.empty()) why += (why.empty() ? "" : "; ") + std::string("validation: ") + val;
  } else {
    const double a = e->calibration.estimate, b = e->validation.estimate;
    const double ratio = std::max(std::abs(a), std::abs(b)) / std::min(std::abs(a), std::abs(b));
    if (a * b <= 0 || !(ratio <= rules.agreement))
      why = "the splits disagree (ratio " + evidence_num(ratio) + ", allowed " + evidence_num(rules.agreement) +
            " with one sign)";
    else if (std::isfinite(e->fitted) && e->fitted != 0 && a * e->fitted < 0)
      why = "the evidence has the opposite sign of the fitted value (" + evidence_num(e->fitted * e->unit_scale) + " " +
            e->unit + ")";
  }
  e->found = why.empty();
  e->verdict = (e->found ? "found: " : "not found: ") + e->quantity + " " + read + (why.empty() ? "" : "; " + why);
}

bool finite(const Vec2& v) { return std::isfinite(v.x()) && std::isfinite(v.y()); }

Vec2 residual_px(const FingerprintSample& s, std::size_t k, std::size_t j) {
  Vec2 nan(kEvidenceNaN, kEvidenceNaN);
  if (k >= s.pred_px.size() || j >= s.pred_px[k].size() || k >= s.meas_px.size() || j >= s.meas_px[k].size())
    return nan;
  const Vec2 r = s.meas_px[k][j] - s.pred_px[k][j];
  return finite(r) ? r : nan;
}

double max_norm_px(const std::vector<Vec2>& field) {
  double m = 0;
  for (const Vec2& d : field)
    if (finite(d)) m = std::max(m, d.norm());
  return m;
}

bool press_frame(const FingerprintSample& s, std::size_t k) {
  return s.in_contact.at(k) != 0 && s.travel_px.at(k) < kPressTravelPx;
}

bool slide_frame(const FingerprintSample& s, std::size_t k) {
  return s.in_contact.at(k) != 0 && s.travel_px.at(k) >= kSlideTravelPx;
}

bool moved_frame(const FingerprintSample& s, std::size_t k) {
  return max_norm_px(s.meas_px.at(k)) >= kMotionThresholdPx;
}

}  // namespace sb
