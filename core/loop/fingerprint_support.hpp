#pragma once
// What every fingerprint shares: the sample it reads, the rules of a finding, and the marker grid's
// neighbourhoods (core/loop/fingerprints.hpp lists the fingerprints; docs/effects.md, "Fingerprints").
#include <cstdint>
#include <limits>
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

// A frame counts for the field's shape when some measured marker moved (the metric's rule,
// kMotionThresholdPx).
bool frame_moved(const std::vector<Vec2>& meas_px);

// The smallest distance between two markers' rest positions (px): the grid pitch.
// Throws std::invalid_argument when the sensor has no two distinct markers.
double marker_pitch_px(const Sensor& sensor);

// The lattice neighbours of each interior marker (those within 1.2 pitches, on markers that have as many
// as the best-surrounded one: 4 on a square grid); empty lists for the others.
std::vector<std::vector<int>> interior_neighbours(const Sensor& sensor);

// Sum over markers with neighbours of |mean of the neighbours - the marker|^2 (px^2); lost markers count 0.
double laplacian_energy(const std::vector<std::vector<int>>& neighbours, const std::vector<Vec2>& field_px);

// Throws std::invalid_argument naming `who` unless the sample has one contact and one held flag per frame.
void require_fingerprint_flags(const FingerprintSample& sample, const char* who);

// One sign and a ratio within `agreement`.
bool splits_agree(double a, double b, double agreement);

// A number as the report prints an estimate (3 significant digits, "nan").
std::string estimate_text(double v);

// The estimate and the values within `agreement` of it (its sign kept).
FingerprintCheck::Band agreement_band(const std::string& name, double estimate, double agreement);

// Sets the check's verdict and consistency: "found on both splits" when neither split misses anything and
// they agree, or what was missing, for the report.
void conclude_finding(FingerprintCheck* check, const std::string& missing_calibration,
                      const std::string& missing_validation, bool agreeing, const FingerprintRules& rules);

}  // namespace sb
