#pragma once
// tool_frame's evidence (core/effects/effect_tool_frame.cpp): the press offset at first contact.
//
// A robot whose zero lies d0 past the skin presses every frame d0 deeper than recorded: the gel starts to move
// d0 of press before the recorded contact. No contact model, whatever its form, moves the gel before contact, so
// motion there is the offset's own signature. Per press that starts at rest: the first frame whose measured field
// departs from the tracker noise, z_k = (sum_j |meas_kj|^2 / sigma^2 - n_k) / sqrt(2 n_k) >= kDetectSigmas (the
// field's energy against the chi-square of n_k noise components, sigma = the split's tracker noise) and stays
// there for kDetectFrames frames, interpolated between frames in the amplitude above the noise (exact for a
// field that grows linearly with the press); the recorded signed depth there, extrapolated
// before contact at the press rate of the first frames in contact (a robot approaches at constant speed). The
// reading is minus that depth: d0 less the small penetration the detection needs (> 0: the gel moved before the
// recorded contact). It counts only when it exceeds one frame of press (the recorded contact's own resolution).
// A negative reading (motion starts after the recorded contact) is the detection's lag as much as a zero short of
// the skin, and is not read: such an offset has no evidence here. The model is not used: a contact model's
// sensitivity at small depth is form, and a comparison with it reads form error as offset (a finite-element gel
// stiffer than HydroShear at first touch reads 0.24 mm that way).
//
// The pivot h (the effect's other parameter) shows in pure tilts: the recorded pose tilts the indenter about the
// apex, the robot about a point h below it, which moves the indenter by h (R z - z), laterally h (R z)_xy. A
// curved indenter tilted in place then touches the gel h (R z)_xy from where the recorded pose puts it, and the
// whole field moves with it. Per frame of a press (in contact, the recorded contact has not travelled) tilted by
// at least kMinPivotTiltRad: the centroid of |meas| minus that of |pred| (the answer's field without the effect),
// over the markers where either field is at least a tenth of its largest; per sample the least-squares h of
// those shifts against the camera's image of (R z)_xy. A centroid does not move with a gain or a symmetric width
// error of the model, which is what tells the pivot from form error. A flat surface on a dome touches it where
// the tilt says whatever the pivot: there the pivot changes only the depth and reads 0 here.
#include "core/loop/evidence.hpp"

namespace sb {

// Per sample: how much press before the recorded contact the measured field departs from noise (metres), and the
// press per frame there; NaN for a sample that does not start at rest, never departs, or never touches.
struct PressOnset {
  std::vector<double> before_contact_m, rate_m;
};
PressOnset press_onsets(const EvidenceSplit& split);

inline constexpr double kMinPivotTiltRad = 0.035;  // 2 degrees: (R z)_xy = 0.035, a 0.035 h shift
inline constexpr std::size_t kMinPivotFrames = 3;  // tilted press frames a sample needs for its reading

// Per sample: the pivot depth below the apex (metres) whose lateral shift h (R z)_xy best explains the measured
// field's centroid against the model's over its tilted press frames; NaN with fewer than kMinPivotFrames.
std::vector<double> pivot_depths_m(const Sensor& sensor, const EvidenceSplit& split);

EffectEvidence tool_frame_evidence(const Sensor& sensor, const EvidenceSplit& calibration,
                                   const EvidenceSplit& validation, const FittedParam& fitted);

}  // namespace sb
