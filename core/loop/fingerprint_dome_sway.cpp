// dome_sway's evidence: the far markers dragged along the slide (fingerprint_dome_sway.hpp).
#include "core/loop/fingerprint_dome_sway.hpp"

#include <algorithm>
#include <cmath>

#include "core/base/format.hpp"

namespace sb {

namespace {

constexpr double kSwayFarFraction = 0.1;  // |pred| below this x the frame's largest: the model says nothing there

// The far markers' mean residual along the slide, and their model field's (the kernel's tail), per sample.
struct Drag {
  double residual = kEvidenceNaN, model = kEvidenceNaN;
};

Drag far_drag(const EvidenceSample& e, double min_slide_m, bool* slid) {
  const FingerprintSample& s = e.fp;
  double sum = 0, model = 0, n = 0;
  for (std::size_t k = 0; k < s.meas_px.size(); ++k) {
    if (s.in_contact[k] == 0 || !(e.slide_m[k].norm() >= min_slide_m) || !moved_frame(s, k)) continue;
    *slid = true;
    const Vec2 along = e.slide_m[k].normalized();  // E's xy are the image's axes
    const double peak = max_norm_px(s.pred_px[k]);
    double fs = 0, fm = 0, fn = 0;
    for (std::size_t j = 0; j < s.pred_px[k].size(); ++j) {
      const Vec2 r = residual_px(s, k, j);
      if (!finite(r) || !(s.pred_px[k][j].norm() < kSwayFarFraction * peak)) continue;
      fs += r.dot(along), fm += std::abs(s.pred_px[k][j].dot(along)), ++fn;
    }
    if (fn > 0) sum += fs / fn, model += fm / fn, ++n;
  }
  if (n == 0) return {};
  return {sum / n, model / n};
}

SplitReading dome_sway_reading(const Sensor& sensor, const EvidenceSplit& split) {
  const double min_slide = kSlideTravelPx * sensor.camera.metres_per_px();
  std::vector<double> drag, model;
  int slides = 0;
  for (const auto& s : split.samples) {
    bool slid = false;
    const Drag d = far_drag(s, min_slide, &slid);
    drag.push_back(d.residual), model.push_back(d.model);
    slides += slid ? 1 : 0;
  }
  SplitReading r = split_reading(split, drag, "slide with markers where the model's field has died away");
  if (!r.missing.empty() && slides > 0)
    r.missing += " (of " + std::to_string(slides) + " slides: in the others the model's field reaches every marker)";
  const MeanEstimate tail = mean_estimate(model);
  r.detail = "the model's own far field along the slide " + format_number(tail.mean, "%.3g", "nan") + " px";
  // A kernel's form error changes its tail by a fraction of itself; the array's mode is not in the model at all.
  if (r.missing.empty() && !(r.estimate > tail.mean))
    r.missing = "the far markers' drag is no larger than the model's own field there (" + r.detail +
                "): a kernel's tail, not the array moving";
  return r;
}

}  // namespace

std::vector<double> far_field_drag_px(const Sensor& sensor, const EvidenceSplit& split) {
  std::vector<double> out;
  bool slid = false;
  const double min_slide = kSlideTravelPx * sensor.camera.metres_per_px();
  for (const auto& s : split.samples) out.push_back(far_drag(s, min_slide, &slid).residual);
  return out;
}

EffectEvidence dome_sway_evidence(const Sensor& sensor, const EvidenceSplit& calibration,
                                  const EvidenceSplit& validation, const FittedParam& fitted) {
  EffectEvidence e;
  e.effect = "dome_sway";
  e.looked_at = "the markers far from the contact (where the model's field has died away), along the slide";
  e.quantity = "far-field drag along the slide";
  e.unit = "px";
  e.fitted = fitted("compliance_m");  // >= 0: the array moves with the slide
  e.calibration = dome_sway_reading(sensor, calibration);
  e.validation = dome_sway_reading(sensor, validation);
  conclude_evidence(&e);
  return e;
}

}  // namespace sb
