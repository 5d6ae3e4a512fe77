#pragma once
// viscoelastic_creep's fingerprint: the change of the measured field while the indenter is held still, and
// after release. Every base model is rate-independent: it predicts no change in either, whatever its form;
// the standard linear solid's (tau, c) are the ones that, undone, leave neither. Needs no model.
#include <vector>

#include "core/loop/fingerprint_support.hpp"

namespace sb {

// The glassy (instantaneous) field that the standard linear solid of the viscoelastic_creep effect, with
// time constant tau_s and creep fraction c, turns into meas_px: the effect run backwards. With
// a = exp(-dt / tau): x_0 = 0, x_k = c d_{k-1} (1 - a) + a x_{k-1}, d_k = meas_k - x_k. A lost marker (NaN)
// keeps its previous glassy value in the filter and is NaN in the output.
std::vector<std::vector<Vec2>> sls_glassy_field(const std::vector<std::vector<Vec2>>& meas_px, double dt_s,
                                                double tau_s, double creep_fraction);

struct CreepFingerprint {
  double tau_s = kFingerprintNaN;
  double creep_fraction = kFingerprintNaN;
  // The evidence: over every run of held frames, the change of the field since the run began (on markers
  // that had moved >= kMotionThresholdPx when it began); over the frames out of contact after a release,
  // the change since the release (on markers that moved >= kMotionThresholdPx in contact: a permanent set
  // left by adhesion is constant and does not count). RMS over its marker-frames at c = 0 ...
  double signal_rms_px = 0;
  double held_rms_px = 0, release_rms_px = 0;  // ... and of its two parts
  double marker_frames = 0;
  // ... and the share of its sum of squares that undoing (tau, c) removes.
  double explained_pct = kFingerprintNaN;
};

// Estimates (tau_s, c) from the measured series alone, as the pair whose glassy field (sls_glassy_field)
// stays constant over the holds and after release: a grid over log tau in [0.01, 10] s and c in [-0.5, 1]
// (the effect's ranges), then a pattern search. NaN estimates when the samples hold no evidence.
// Throws std::invalid_argument when a sample lacks one contact or held flag per frame.
CreepFingerprint creep_fingerprint(const std::vector<FingerprintSample>& samples);

// The finding on both splits (creep_fingerprint of each; the sensor is not read): tau_s and creep_fraction held
// at the calibration estimate (evidence beyond model form).
FingerprintCheck creep_check(const Sensor& sensor, const std::vector<FingerprintSample>& calibration,
                             const std::vector<FingerprintSample>& validation, const FingerprintRules& rules);

}  // namespace sb
