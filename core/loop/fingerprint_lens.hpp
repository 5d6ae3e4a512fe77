#pragma once
// lens_distortion's fingerprint. The markers are printed on a lattice and the lens images it bent about the
// principal point; no contact model touches the rest positions, so on a lattice the rest grid is the evidence
// (core/loop/rest_grid_lens.hpp). When the rest grid is not a lattice (the TacTip's dome), the part of the
// residual that is not symmetric about the contact: a press or twist of an axisymmetric indenter gives a field
// symmetric about the contact centre, and so does a contact model's error of it; the lens, fixed in the image,
// is not.
#include <vector>

#include "core/loop/fingerprint_support.hpp"

namespace sb {

// The k1 term of the lens_distortion effect: D(m + d) - D(m) - d at k1 = 1, k2 = 0, for a marker at rest
// m (px) displaced by d (px). The effect's field is d + k1 lens_k1_pattern(m, d) + O(k2), exactly linear
// in k1 for a given undistorted d.
Vec2 lens_k1_pattern(const Camera& camera, const Vec2& m_px, const Vec2& d_px);

struct LensFingerprint {
  double k1 = kFingerprintNaN;
  double k1_stderr = kFingerprintNaN;  // from the scatter of what the nuisance fields and k1 leave
  double signal_rms_px = 0;            // RMS of k1 x the asymmetric part of the pattern over the frames used
  double frames = 0;                   // frames used: in contact, a marker moved, the contact has not travelled
};

// Regresses the residual (meas - pred) on the lens pattern, frame by frame, after projecting out of both
// what a contact model's error of a press or twist can hold: fields symmetric about the contact centre
// (radial and tangential, any profile of the distance: hat functions one marker pitch apart), a uniform
// translation, and the field scaled near the gel's sides (within half and one thickness: a finite pad's
// sides respond unlike a half-space, and that pattern is fixed to the gel, not the contact). Only frames
// whose contact has not travelled (travel_px < 0.5 px) are used: a slide is not symmetric. The pattern is
// that of the measured field undistorted by the estimate (the lens acts on the true field, which the
// measurement holds better than a model with a form error), with the pattern of the model's field as its
// instrument (it does not share the measurement's noise); the estimate is the fixed point, found by secant
// steps. NaN when no frame qualifies.
LensFingerprint lens_fingerprint(const Sensor& sensor, const std::vector<FingerprintSample>& samples);

// Whether the lens's finding compares the measurement with the model's field: only when the sensor's rest grid
// is not a lattice.
bool lens_needs_model(const Sensor& sensor);

// The finding. On a lattice: the rest grid, the same on both splits; found when |k1| >= rules.min_k1 and
// >= rules.k1_sigmas standard errors, then k1 is held at it and k2 at 0 (accepted on its evidence). Otherwise the
// residual's asymmetry (lens_fingerprint on each split; needs pred_px); the whole-field fit of k1 must end within
// the agreement ratio of its estimate, k2 held at 0.
FingerprintCheck lens_check(const Sensor& sensor, const std::vector<FingerprintSample>& calibration,
                            const std::vector<FingerprintSample>& validation, const FingerprintRules& rules);

}  // namespace sb
