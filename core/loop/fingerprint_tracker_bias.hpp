#pragma once
// tracker_bias's evidence (core/effects/effect_tracker_bias.cpp): a constant offset on the moving markers
// whatever the motion's direction.
//
// A tracker's centroid bias is fixed in the image: b on every moving marker (|meas| > kMotionThresholdPx),
// in every sample. A contact model's form error follows the load: it is symmetric about a press's contact and
// turns with a slide's direction, so over samples of different directions its mean cancels. Per sample the
// mean residual over its moving marker-frames (a vector); the reading is the component (x or y) whose mean over
// samples is the more significant (px). The effect's gain (tracked / true) is not read: a model's stiffness
// error is a gain too.
#include "core/loop/evidence.hpp"

namespace sb {

// Per sample: the mean residual over the moving marker-frames (px), NaN without any.
std::vector<Vec2> moving_marker_offset_px(const EvidenceSplit& split);

EffectEvidence tracker_bias_evidence(const Sensor& sensor, const EvidenceSplit& calibration,
                                     const EvidenceSplit& validation, const FittedParam& fitted);

// The component (0: x, 1: y) of per-sample vectors whose mean is more significant on the calibration split, and
// the readings of that component on both splits (shared with gravity_preload).
int significant_component(const std::vector<Vec2>& calibration);
std::vector<double> component(const std::vector<Vec2>& v, int axis);

}  // namespace sb
