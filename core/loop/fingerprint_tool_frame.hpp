#pragma once
// tool_frame's evidence (core/effects/effect_tool_frame.cpp): the press offset at first contact.
//
// A robot whose zero lies d0 past the skin presses every frame d0 deeper than recorded, so the measured field
// starts to move d0 of press before (d0 > 0) or after (d0 < 0) the recorded contact. Any contact model, whatever
// its form, predicts no field before contact and a field that grows from zero at the recorded contact; a form
// error changes how fast it grows, not where it starts. Per press that starts at rest (its first frame below the
// threshold in both the measurement and the model): the first crossing of the largest marker displacement over
// a threshold T, interpolated between frames, in the measurement (t_m) and in the answer's field without the
// effect (t_p); d0 = rate (t_p - t_m), rate the recorded penetration per frame over the first frames in contact.
//   T = max(kMotionThresholdPx, 10 sigma): the noise's largest marker over a frame stays near 4 sigma.
// Read again at 2T: a true offset is the same at both, while a model softer or stiffer than the gel reaches a
// threshold later or earlier by a depth that grows with it; readings that differ by more than the agreement
// ratio count as a difference of sensitivity, not of zero. The pivot (the effect's other parameter) shows only
// through tilted presses and is reported with the fit, not read here.
#include "core/loop/evidence.hpp"

namespace sb {

// The press offset (metres, > 0: the presses are deeper than recorded) on one split; `threshold_factor`
// multiplies T (1 and 2 are the two readings). NaN per sample that does not start at rest or never crosses.
std::vector<double> press_offsets_m(const EvidenceSplit& split, double threshold_factor);

EffectEvidence tool_frame_evidence(const Sensor& sensor, const EvidenceSplit& calibration,
                                   const EvidenceSplit& validation, const FittedParam& fitted);

}  // namespace sb
