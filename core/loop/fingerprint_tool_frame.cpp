// tool_frame's evidence: the gel moving before the recorded contact (fingerprint_tool_frame.hpp).
#include "core/loop/fingerprint_tool_frame.hpp"

#include <algorithm>
#include <cmath>

#include "core/base/format.hpp"

namespace sb {

namespace {

constexpr double kDetectSigmas = 5.0;     // z of the field's energy over the noise's: 5 sigma of a chi-square
constexpr std::size_t kDetectFrames = 3;  // and it stays there (a tracker glitch is one frame)
constexpr std::size_t kRateFrames = 3;    // frames in contact that set the press rate
constexpr double kMinNoisePx = 0.005;     // a noise estimate below this (noise-free data) counts as this

// Per frame: the measured field's amplitude above the noise, sqrt(max(0, sum_j |meas_kj|^2 - n_k sigma^2)) (px),
// and the amplitude at which it departs, sqrt(kDetectSigmas sqrt(2 n_k)) sigma (z = kDetectSigmas). Interpolating
// the amplitude between frames is exact for a field growing linearly with the press (the energy is not).
struct Amplitude {
  std::vector<double> above, threshold;
};
Amplitude amplitude(const FingerprintSample& s, double sigma) {
  Amplitude a;
  for (const auto& frame : s.meas_px) {
    double e = 0, n = 0;
    for (const Vec2& d : frame)
      if (finite(d)) e += d.squaredNorm(), n += 2;
    a.above.push_back(n > 0 ? std::sqrt(std::max(0.0, e - n * sigma * sigma)) : kEvidenceNaN);
    a.threshold.push_back(n > 0 ? std::sqrt(kDetectSigmas * std::sqrt(2 * n)) * sigma : kEvidenceNaN);
  }
  return a;
}

// The first k at or above the threshold for kDetectFrames frames, interpolated between k - 1 and k; NaN when the
// sample does not start below it or never departs.
double departure(const Amplitude& a) {
  const auto over = [&](std::size_t k) { return a.above[k] >= a.threshold[k]; };
  if (a.above.empty() || over(0) || !std::isfinite(a.above[0])) return kEvidenceNaN;
  for (std::size_t k = 1; k + kDetectFrames <= a.above.size(); ++k) {
    bool stays = true;
    for (std::size_t i = k; i < k + kDetectFrames; ++i) stays = stays && over(i);
    if (stays) return static_cast<double>(k - 1) + (a.threshold[k] - a.above[k - 1]) / (a.above[k] - a.above[k - 1]);
  }
  return kEvidenceNaN;
}

}  // namespace

PressOnset press_onsets(const EvidenceSplit& split) {
  const double sigma = std::max(std::isfinite(split.noise_px) ? split.noise_px : 0.0, kMinNoisePx);
  PressOnset out;
  for (const auto& s : split.samples) {
    double before = kEvidenceNaN, rate = kEvidenceNaN;
    const auto first = std::find(s.fp.in_contact.begin(), s.fp.in_contact.end(), 1);
    const auto kc = static_cast<std::size_t>(first - s.fp.in_contact.begin());
    const std::size_t k1 = std::min(kc + kRateFrames, s.depth_m.size() - 1);
    if (first != s.fp.in_contact.end() && k1 > kc) {
      rate = (s.depth_m[k1] - s.depth_m[kc]) / static_cast<double>(k1 - kc);
      const double t = departure(amplitude(s.fp, sigma));
      if (rate > 0 && std::isfinite(t)) {
        // The recorded signed depth at t: the penetration in contact, the approach at `rate` before it.
        const double kct = static_cast<double>(kc);
        double depth = s.depth_m[kc] - rate * (kct - t);
        if (t >= kct) {
          const auto k = static_cast<std::size_t>(t);
          const double f = t - static_cast<double>(k);
          depth = k + 1 < s.depth_m.size() ? (1 - f) * s.depth_m[k] + f * s.depth_m[k + 1] : s.depth_m[k];
        }
        before = -depth;
      }
    }
    if (!(rate > 0)) rate = kEvidenceNaN;
    out.before_contact_m.push_back(before);
    out.rate_m.push_back(rate);
  }
  return out;
}

namespace {

SplitReading tool_frame_reading(const EvidenceSplit& split) {
  const PressOnset o = press_onsets(split);
  SplitReading r = split_reading(
      split, o.before_contact_m,
      "recorded frame by frame from rest depart from the noise (a single image per press shows no onset)");
  const double step = mean_estimate(o.rate_m).mean;
  r.detail = "one frame of press " + format_number(1e3 * step, "%.3g", "nan") + " mm";
  if (!r.missing.empty()) return r;
  if (!(r.estimate > 0))
    r.missing = "the gel starts to move after the recorded contact (" + format_number(-1e3 * r.estimate, "%.3g") +
                " mm into it): the detection's own lag, no offset to read";
  else if (!(r.estimate > step))
    r.missing = "the gel starts to move within one frame of press of the recorded contact (" + r.detail + ")";
  return r;
}

}  // namespace

EffectEvidence tool_frame_evidence(const Sensor& /*sensor*/, const EvidenceSplit& calibration,
                                   const EvidenceSplit& validation, const FittedParam& fitted) {
  EffectEvidence e;
  e.effect = "tool_frame";
  e.looked_at = "where the measured field departs from the tracker noise against the recorded contact, in presses";
  e.quantity = "press before the recorded contact at which the gel moves";
  e.unit = "mm";
  e.unit_scale = 1e3;
  e.fitted = fitted("press_offset_m");
  e.calibration = tool_frame_reading(calibration);
  e.validation = tool_frame_reading(validation);
  conclude_evidence(&e);
  return e;
}

}  // namespace sb
