// tool_frame's evidence: the press offset at first contact (fingerprint_tool_frame.hpp).
#include "core/loop/fingerprint_tool_frame.hpp"

#include <algorithm>
#include <cmath>

#include "core/base/format.hpp"
#include "core/calibration/metrics.hpp"

namespace sb {

namespace {

constexpr double kNoiseSigmas = 10.0;  // T over the tracker noise
constexpr std::size_t kRateFrames = 3;  // frames in contact that set the press rate

// The first crossing of `threshold` by a[k], interpolated between frames; NaN when a[0] is at or above it or it
// is never reached.
double crossing(const std::vector<double>& a, double threshold) {
  if (a.empty() || !(a[0] < threshold)) return kEvidenceNaN;
  for (std::size_t k = 1; k < a.size(); ++k)
    if (a[k] >= threshold) return static_cast<double>(k - 1) + (threshold - a[k - 1]) / (a[k] - a[k - 1]);
  return kEvidenceNaN;
}

// Recorded penetration per frame at first contact: the mean increment over the first kRateFrames in contact.
double press_rate_m(const EvidenceSample& s) {
  const auto first = std::find(s.fp.in_contact.begin(), s.fp.in_contact.end(), 1);
  if (first == s.fp.in_contact.end()) return kEvidenceNaN;
  const auto k0 = static_cast<std::size_t>(first - s.fp.in_contact.begin());
  const std::size_t k1 = std::min(k0 + kRateFrames, s.depth_m.size() - 1);
  if (k1 <= k0) return kEvidenceNaN;
  const double rate = (s.depth_m[k1] - s.depth_m[k0]) / static_cast<double>(k1 - k0);
  return rate > 0 ? rate : kEvidenceNaN;
}

std::vector<double> largest(const std::vector<std::vector<Vec2>>& field) {
  std::vector<double> a;
  a.reserve(field.size());
  for (const auto& f : field) a.push_back(max_norm_px(f));
  return a;
}

SplitReading read(const EvidenceSplit& split) {
  SplitReading r = reading_of(press_offsets_m(split, 1.0), "start at rest and cross the threshold in a press");
  r.noise_px = split.noise_px;
  const SplitReading twice = reading_of(press_offsets_m(split, 2.0), "cross twice the threshold");
  r.detail = "at twice the threshold " + format_number(1e3 * twice.estimate, "%.3g", "nan") + " mm";
  const double a = r.estimate, b = twice.estimate;
  const bool significant = std::abs(a) >= EvidenceRules{}.sigmas * r.std_error;
  if (r.missing.empty() && significant &&
      (!(a * b > 0) || std::max(std::abs(a), std::abs(b)) > EvidenceRules{}.agreement * std::min(std::abs(a), std::abs(b))))
    r.missing = "the onset shift changes with the threshold (" + format_number(1e3 * a, "%.3g") + " mm at T, " +
                format_number(1e3 * b, "%.3g", "nan") +
                " mm at 2T): the model's sensitivity differs from the gel's, its zero does not";
  return r;
}

}  // namespace

std::vector<double> press_offsets_m(const EvidenceSplit& split, double threshold_factor) {
  const double sigma = std::isfinite(split.noise_px) ? split.noise_px : 0.0;
  const double threshold = threshold_factor * std::max(kMotionThresholdPx, kNoiseSigmas * sigma);
  std::vector<double> out;
  for (const auto& s : split.samples) {
    const double rate = press_rate_m(s);
    const double tm = crossing(largest(s.fp.meas_px), threshold), tp = crossing(largest(s.fp.pred_px), threshold);
    out.push_back(rate * (tp - tm));
  }
  return out;
}

EffectEvidence tool_frame_evidence(const Sensor& /*sensor*/, const EvidenceSplit& calibration,
                                   const EvidenceSplit& validation, const FittedParam& fitted) {
  EffectEvidence e;
  e.effect = "tool_frame";
  e.looked_at = "where the measured field starts to move against where the model's does, in presses from rest";
  e.quantity = "press offset at first contact";
  e.unit = "mm";
  e.unit_scale = 1e3;
  e.fitted = fitted("press_offset_m");
  e.calibration = read(calibration);
  e.validation = read(validation);
  conclude_evidence(&e);
  return e;
}

}  // namespace sb
