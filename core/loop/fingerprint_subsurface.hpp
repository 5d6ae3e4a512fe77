#pragma once
// subsurface_markers' fingerprint: how much the measured field is low-passed on the marker grid against the
// model's field (their fine-scale content, the energy of the grid Laplacian).
#include <vector>

#include "core/loop/fingerprint_support.hpp"

namespace sb {

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

// The finding on both splits (subsurface_fingerprint of each; needs pred_px), as the lens on a rest grid that
// is not a lattice, with depth_m.
FingerprintCheck subsurface_check(const Sensor& sensor, const std::vector<FingerprintSample>& calibration,
                                  const std::vector<FingerprintSample>& validation, const FingerprintRules& rules);

}  // namespace sb
