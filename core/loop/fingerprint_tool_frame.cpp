// tool_frame's evidence: the gel moving before the recorded contact (fingerprint_tool_frame.hpp).
#include "core/loop/fingerprint_tool_frame.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <utility>

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

// Each marker's neighbours within 1.5 pitches: where the model's field's gradient is read.
std::vector<std::vector<std::size_t>> gradient_neighbours(const Sensor& sensor) {
  const auto& m = sensor.markers_rest_px;
  const double reach = 1.5 * marker_pitch_px(sensor);
  std::vector<std::vector<std::size_t>> nb(m.size());
  for (std::size_t i = 0; i < m.size(); ++i)
    for (std::size_t j = 0; j < m.size(); ++j)
      if (i != j && (m[i] - m[j]).norm() < reach) nb[i].push_back(j);
  return nb;
}

// The shift s (px) of the model's field that best explains the measured one up to a gain: meas = g pred(m - s)
// ~ g pred - J (g s), J the field's gradient at each marker from its neighbours (least squares), solved for g and
// t = g s over the markers; nullopt where the gain is not positive or the system is singular. Unlike a centroid,
// the view's edge does not shrink it.
std::optional<Vec2> field_shift_px(const Sensor& sensor, const std::vector<std::vector<std::size_t>>& nb,
                                   const std::vector<Vec2>& meas, const std::vector<Vec2>& pred) {
  const auto& m = sensor.markers_rest_px;
  Eigen::Matrix3d AtA = Eigen::Matrix3d::Zero();
  Eigen::Vector3d Atb = Eigen::Vector3d::Zero();
  for (std::size_t j = 0; j < m.size(); ++j) {
    if (!finite(meas[j]) || !finite(pred[j])) continue;
    Eigen::Matrix2d dm_dm = Eigen::Matrix2d::Zero(), df_dm = Eigen::Matrix2d::Zero();
    for (std::size_t n : nb[j]) {
      if (!finite(pred[n])) continue;
      const Vec2 dm = m[n] - m[j], df = pred[n] - pred[j];
      dm_dm += dm * dm.transpose(), df_dm += df * dm.transpose();
    }
    if (!(std::abs(dm_dm.determinant()) > 1e-9 * dm_dm.squaredNorm())) continue;
    const Eigen::Matrix2d J = df_dm * dm_dm.inverse();
    Eigen::Matrix<double, 2, 3> A;
    A.col(0) = pred[j];
    A.rightCols<2>() = -J;
    AtA += A.transpose() * A;
    Atb += A.transpose() * meas[j];
  }
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(AtA);
  if (ldlt.info() != Eigen::Success || !(AtA.determinant() > 0)) return std::nullopt;
  const Eigen::Vector3d x = ldlt.solve(Atb);
  if (!(x(0) > 0.1)) return std::nullopt;
  return Vec2(x.tail<2>() / x(0));
}

}  // namespace

std::vector<double> pivot_depths_m(const Sensor& sensor, const EvidenceSplit& split) {
  const auto nb = gradient_neighbours(sensor);
  std::vector<double> out;
  for (const auto& s : split.samples) {
    double shift_dot_dir = 0, dir_sq = 0;
    std::size_t frames = 0;
    for (std::size_t k = 0; k < s.approach_xy.size() && k < s.fp.pred_px.size(); ++k) {
      if (!press_frame(s.fp, k) || !moved_frame(s.fp, k) || !(s.tilt_rad[k] >= kMinPivotTiltRad)) continue;
      const auto shift = field_shift_px(sensor, nb, s.fp.meas_px[k], s.fp.pred_px[k]);
      if (!shift) continue;
      const Vec2 per_metre_px = sensor.camera.px_displacement(s.approach_xy[k]);  // image shift per metre of h
      shift_dot_dir += shift->dot(per_metre_px);
      dir_sq += per_metre_px.squaredNorm();
      ++frames;
    }
    out.push_back(frames >= kMinPivotFrames && dir_sq > 0 ? shift_dot_dir / dir_sq : kEvidenceNaN);
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

// One of tool_frame's two parameters: its two splits' readings and the finding, in millimetres.
EffectEvidence parameter_evidence(const std::string& looked_at, const std::string& quantity, double fitted,
                                  SplitReading calibration, SplitReading validation) {
  EffectEvidence e;
  e.effect = "tool_frame";
  e.looked_at = looked_at;
  e.quantity = quantity;
  e.unit = "mm";
  e.unit_scale = 1e3;
  e.fitted = fitted;
  e.calibration = std::move(calibration);
  e.validation = std::move(validation);
  conclude_evidence(&e);
  return e;
}

EffectEvidence press_offset_evidence(const EvidenceSplit& calibration, const EvidenceSplit& validation,
                                     const FittedParam& fitted) {
  return parameter_evidence(
      "where the measured field departs from the tracker noise against the recorded contact, in presses",
      "press before the recorded contact at which the gel moves", fitted("press_offset_m"),
      tool_frame_reading(calibration), tool_frame_reading(validation));
}

EffectEvidence pivot_evidence(const Sensor& sensor, const EvidenceSplit& calibration, const EvidenceSplit& validation,
                              const FittedParam& fitted) {
  const std::string what = "with " + std::to_string(kMinPivotFrames) + " frames of a press tilted by >= 2 deg in place";
  return parameter_evidence("where the measured field sits against the model's in presses tilted in place",
                            "pivot depth below the apex that moves the contact so", fitted("pivot_depth_m"),
                            split_reading(calibration, pivot_depths_m(sensor, calibration), what),
                            split_reading(validation, pivot_depths_m(sensor, validation), what));
}

}  // namespace

EffectEvidence tool_frame_evidence(const Sensor& sensor, const EvidenceSplit& calibration,
                                   const EvidenceSplit& validation, const FittedParam& fitted) {
  const EffectEvidence press = press_offset_evidence(calibration, validation, fitted);
  const EffectEvidence pivot = pivot_evidence(sensor, calibration, validation, fitted);
  // The effect is found when either parameter's evidence is; the report leads with the one found.
  const bool pivot_leads = pivot.found && !press.found;
  EffectEvidence e = pivot_leads ? pivot : press;
  const EffectEvidence& other = pivot_leads ? press : pivot;
  e.looked_at += "; and " + other.looked_at;
  e.verdict += "; and " + other.verdict;
  return e;
}

}  // namespace sb
