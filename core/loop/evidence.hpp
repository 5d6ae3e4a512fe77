#pragma once
// Evidence for an effect in the loop's answer (docs/effects.md, "Evidence: found or a correction of unshown
// cause"): what the effect does to the measurement that the base model's form error cannot, read on each split
// from the data and from the answer's field without that effect. One reader per effect, in its own file pair
// (fingerprint_<effect>.hpp); this file holds what they share: the samples they see, one split's reading, and
// the one rule that turns two readings into a finding.
//
// The rule (conclude_evidence), the same for every effect:
//  - each split's reading is an estimate over its samples, with the standard error of their scatter (a sample
//    is the unit: its frames are correlated), so significance is relative to the split's own noise and
//    sample-to-sample variation, not to a threshold tuned on a set;
//  - a split shows the effect when its estimate is at least `sigmas` standard errors from zero and the reader
//    found no reason against it (its own form-error check, the reading's `missing`);
//  - found when both splits show it, with one sign and a ratio within `agreement`, and that sign is the
//    fitted parameter's (the evidence says what the fit says, not merely that something is there).
// A selected effect that is not found is a correction of unshown cause: it lowers the error, but nothing
// outside the held-out gain says the effect is why.
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "core/loop/fingerprints.hpp"
#include "core/sensor/sensor.hpp"

namespace sb {

inline constexpr double kEvidenceNaN = std::numeric_limits<double>::quiet_NaN();

// One sample as an evidence reader sees it: the fingerprint's view (fp.pred_px is the answer's field without the
// effect under test, at the answer's parameters), and per frame the recorded pose's penetration and tilt.
struct EvidenceSample {
  FingerprintSample fp;
  std::vector<double> depth_m;   // [frame] the indenter's penetration by the recorded pose (0 out of contact)
  std::vector<double> tilt_rad;  // [frame] angle between the indenter's approach axis and E's z
  // [frame] the indenter's lateral travel in E's xy since its first frame in contact (metres; 0 before): the
  // slide, also where the contact centre does not move (a flat slid over a dome touches it where it tilts).
  std::vector<Vec2> slide_m;
  // [frame] the lateral part of the indenter's approach axis, (R_EI z)_xy: sin of the tilt along its direction
  // (a pivot h below the apex moves the indenter by h times this: tool_frame's pivot).
  std::vector<Vec2> approach_xy;
  // [frame][marker] each marker's penetration into the indenter (effects::marker_penetration); filled only for
  // the readers that ask for it (EvidenceEntry::needs_marker_depth), else empty.
  std::vector<std::vector<double>> marker_depth_m;
};

// One split as the readers see it: its samples and its tracker noise (tracker_noise_px of their measurements).
struct EvidenceSplit {
  std::vector<EvidenceSample> samples;
  double noise_px = kEvidenceNaN;
};

// One split's reading of an effect's evidence.
struct SplitReading {
  double estimate = kEvidenceNaN;   // the effect's quantity read from the evidence (units: EffectEvidence::unit)
  double std_error = kEvidenceNaN;  // from the scatter of the per-sample estimates
  double samples = 0;               // samples that contributed
  double noise_px = kEvidenceNaN;   // the split's tracker noise (tracker_noise_px), for the report
  std::string detail;               // further numbers the reader read, for the report
  std::string missing;              // non-empty: why this split holds no reading, or why it does not count
};

struct EvidenceRules {
  double sigmas = 3.0;     // a split shows the effect at >= this many standard errors from zero
  double agreement = 1.5;  // the splits' estimates: one sign and a ratio within this (as the fingerprints')
  double min_samples = 3;  // fewer samples than this carry no scatter to judge by
};

// The evidence for one effect of the answer and the finding.
struct EffectEvidence {
  std::string effect;
  std::string looked_at;         // what was read, in a phrase
  std::string quantity, unit;    // what the estimate is ("press offset", "mm")
  double unit_scale = 1;         // estimate * unit_scale is in `unit`
  double fitted = kEvidenceNaN;  // the answer's value of the matching parameter (same units as estimate)
  SplitReading calibration, validation;
  bool found = false;
  std::string verdict;  // "found: ..." or "not found: ..." with the numbers
};

// The answer's fitted value of one of the effect's own parameters ("press_offset_m"); NaN when it has none.
using FittedParam = std::function<double(const std::string& name)>;

// Mean and standard error of per-sample values (NaN entries skipped; std_error NaN for fewer than 2).
struct MeanEstimate {
  double mean = kEvidenceNaN, std_error = kEvidenceNaN;
  double n = 0;
};
MeanEstimate mean_estimate(const std::vector<double>& values);

// The reading of per-sample values: their mean and standard error, `missing` set when fewer than
// rules.min_samples contributed (naming `what` the samples had to show).
SplitReading reading_of(const std::vector<double>& per_sample, const std::string& what,
                        const EvidenceRules& rules = {});

// reading_of the split's per-sample values, with the split's noise recorded.
SplitReading split_reading(const EvidenceSplit& split, const std::vector<double>& per_sample, const std::string& what);

// Applies the rule above to e->calibration and e->validation: sets found and verdict.
void conclude_evidence(EffectEvidence* e, const EvidenceRules& rules = {});

// Shared views of a frame: the residual meas - pred (NaN where either is NaN or missing), the largest finite
// |meas| or |pred| over the markers, and whether a frame is a press frame (in contact, the contact has not
// travelled kPressTravelPx) or a slide frame (in contact, travelled at least kSlideTravelPx).
inline constexpr double kPressTravelPx = 0.5;  // as the lens fingerprint's "has not travelled"
inline constexpr double kSlideTravelPx = 1.0;  // twice that: a slide, not the press's own centre wander
Vec2 residual_px(const FingerprintSample& s, std::size_t k, std::size_t j);
double max_norm_px(const std::vector<Vec2>& field);
bool press_frame(const FingerprintSample& s, std::size_t k);
bool slide_frame(const FingerprintSample& s, std::size_t k);
bool moved_frame(const FingerprintSample& s, std::size_t k);  // a measured marker moved >= kMotionThresholdPx
bool finite(const Vec2& v);

}  // namespace sb
