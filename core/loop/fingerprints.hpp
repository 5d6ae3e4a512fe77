#pragma once
// Fingerprints: for an effect, the evidence that the base model's form error cannot fake, and the effect's
// main parameter estimated from that evidence alone (docs/effects.md, "Fingerprints").
//
// A whole-field fit of an effect over a model whose form is wrong by ~1 px uses the effect's parameters to
// patch that form (creep as a slow gain, subsurface attenuation as a gain). A fingerprint looks where the
// effect shows and a rate-independent contact model's error cannot:
//  - creep: the change of the measured field while the indenter is held still, and its change after
//    release. Every base model is rate-independent: it predicts no change in either, whatever its form;
//    the standard linear solid's (tau, c) are the ones that, undone, leave neither. Needs no model.
//  - lens distortion: the rest grid (core/loop/rest_grid_lens.hpp). The markers are printed on a lattice and
//    the lens images it bent about the principal point; no contact model touches the rest positions. When
//    the rest grid is not a lattice (the TacTip's dome), the part of the residual that is not symmetric about
//    the contact: a press or twist of an axisymmetric indenter gives a field symmetric about the contact
//    centre, and so does a contact model's error of it; the lens, fixed in the image, is not.
//  - subsurface markers: how much the measured field is low-passed on the marker grid against the model's
//    field (their fine-scale content, the energy of the grid Laplacian).
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "core/calibration/metrics.hpp"
#include "core/geometry/pose.hpp"
#include "core/loop/residual_select.hpp"
#include "core/sensor/sensor.hpp"

namespace sb {

// One sample as a fingerprint sees it.
struct FingerprintSample {
  double dt_s = 0.02;
  std::vector<std::vector<Vec2>> meas_px;  // [frame][marker]; NaN where the tracker lost the marker
  std::vector<std::vector<Vec2>> pred_px;  // [frame][marker]: the reference model's field (lens, subsurface)
  std::vector<std::uint8_t> in_contact;    // [frame]: the indenter is in the gel
  std::vector<std::uint8_t> held;          // [frame]: in the gel and its pose equals the previous frame's
  std::vector<Vec2> contact_centre_px;     // [frame]: the contact centre in the image (lens; any value out of contact)
  std::vector<double> travel_px;           // [frame]: its tangential travel since first contact (lens)
};

inline constexpr double kFingerprintNaN = std::numeric_limits<double>::quiet_NaN();

// ------------------------------------------------------------------------------------------ creep

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

// ------------------------------------------------------------------------------------------- lens

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

// ------------------------------------------------------------------------------------- subsurface

// The fine-scale content of a field on the marker grid: sum over markers with four lattice neighbours
// (at the grid pitch) of |mean of the neighbours - the marker|^2 (px^2).
double grid_laplacian_energy(const Sensor& sensor, const std::vector<Vec2>& field_px);

// The tracker's noise per image component (px), read from the measurement alone: the second difference in time
// of every measured marker series, x_{k+1} - 2 x_k + x_{k-1}, has standard deviation sqrt(6) sigma for white
// noise of sigma and far less for the smooth motion of a quasi-static load; its median absolute value (robust
// to the jumps of slip and of lost markers) over 0.6745 sqrt(6). NaN when no marker has 3 finite frames in a row.
double tracker_noise_px(const std::vector<FingerprintSample>& samples);

struct SubsurfaceFingerprint {
  double depth_m = kFingerprintNaN;
  double measured_energy_px2 = 0;  // grid Laplacian energy of the measured fields (frames where a marker moved)
  double model_energy_px2 = 0;     // of the model's fields, unsmoothed
  double measured_fine_fraction = kFingerprintNaN;  // those over the fields' own energy sum |d|^2 (diagnostic)
  double model_fine_fraction = kFingerprintNaN;
  double frames = 0;
  // Whether the reading is evidence: what the best gain times the model's field smoothed at depth_m leaves of
  // the measured Laplacian (px^2), against what the tracker noise alone would leave there: sigma^2 times
  // noise_weight, the sum over the Laplacian components used of (1 + 1/n), n the marker's neighbours (sigma =
  // tracker_noise_px). Near 1 the model explains the grid-scale content up to noise and the depth is read; far
  // above it, the model's form is wrong at the grid scale and the reading is as much that error as depth.
  double fine_misfit_px2 = kFingerprintNaN;
  double noise_weight = 0;
  double noise_px = kFingerprintNaN;
};

// The depth h whose smoothing (the subsurface_markers effect) makes the model's fields' grid Laplacian best
// match the measured fields' Laplacian, up to one gain (a gain, the effect's attenuation or the model's
// stiffness, drops out; a smooth model-form error has almost no Laplacian), over the frames where a
// measured marker moved: a scan of h over [0, 5 mm] in 0.1 mm steps, then golden-section search. 0 when
// smoothing the model only makes the match worse (no sign of depth); NaN when no frame has a marker that moved.
SubsurfaceFingerprint subsurface_fingerprint(const Sensor& sensor, const std::vector<FingerprintSample>& samples);

// ------------------------------------------------------------------------------ the finding

// When an estimate counts as found on one split, and when the two splits agree.
struct FingerprintRules {
  double agreement = 1.5;            // the splits' estimates have one sign and a ratio within this
  double min_signal_px = 0.15;       // creep: the evidence's RMS above tracker noise (0.1 px at 0.05 px noise)
  double min_explained_pct = 50.0;   // creep: undoing (tau, c) removes at least this share of it
  double min_creep_fraction = 0.02;  // creep: |c| below this is no creep
  double min_k1 = 0.02;              // lens: |k1| below this moves a corner marker's displacement < 6 %
  double k1_sigmas = 3.0;            // lens: and |k1| at least this many standard errors (rest grid or residual)
  double min_depth_fraction = 0.25;  // subsurface: depth below this fraction of the marker pitch is not seen
  // subsurface: the grid-scale misfit left at the depth within this many times the noise's (measured: 1.0 with
  // the model exact, 68-146 for every model on the FE twin, whose form is wrong at the grid scale)
  double max_fine_misfit_over_noise = 4.0;
  double min_noise_px = 0.005;  // subsurface: a noise estimate below this (noise-free data) counts as this
};

// The effects that have a fingerprint (the registry's keys, catalogue ids), and whether it compares the
// measurement with the model's field (the lens does only when the sensor's rest grid is not a lattice).
std::vector<std::string> fingerprinted_effects();
bool has_fingerprint(const std::string& effect_id);
bool fingerprint_needs_model(const std::string& effect_id, const Sensor& sensor);

// The fingerprint of `effect_id` on each split and the finding (FingerprintCheck): creep holds tau_s and
// creep_fraction at the calibration estimate (evidence beyond model form). Lens, when the sensor's rest grid is
// a lattice: the rest grid is the evidence, the same on both splits; found when |k1| >= rules.min_k1 and
// >= rules.k1_sigmas standard errors, then k1 is held at it and k2 at 0 (evidence beyond model form, accepted on
// it: FingerprintCheck::Acceptance::kEvidence); not found whatever the residual says. Lens on a rest grid that is not a
// lattice: the residual's asymmetry; the whole-field fit of k1 must end within the agreement ratio of its estimate, k2
// held at 0 (a second radial term is not identified on a marker grid this coarse). Subsurface as that lens,
// with depth_m. nullopt for an effect without a fingerprint. The samples need pred_px when
// fingerprint_needs_model(effect_id, sensor).
std::optional<FingerprintCheck> fingerprint_check(const std::string& effect_id, const Sensor& sensor,
                                                  const std::vector<FingerprintSample>& calibration,
                                                  const std::vector<FingerprintSample>& validation,
                                                  const FingerprintRules& rules = {});

}  // namespace sb
