#pragma once
// camera_misalignment's evidence (core/effects/effect_camera_misalignment.cpp): every displacement turned by the
// same angle, whatever the motion.
//
// A camera rolled by theta against the gel frame turns every measured displacement by theta: presses, slides and
// twists alike. A contact model's form error about an axisymmetric indenter keeps each field's mirror symmetry
// about the load, so the angle from the model's displacement to the measured one averages out over markers
// (mirror images turn by opposite angles). Per sample, theta = atan2(sum pred x meas, sum pred . meas) over its
// moving marker-frames (|meas| >= kMotionThresholdPx); the reading is its mean over samples (rad). The effect's
// scale is not read: a model's stiffness error is a scale too.
#include "core/loop/evidence.hpp"

namespace sb {

// Per sample: the turn from the model's field to the measured one (rad), NaN without moving markers.
std::vector<double> field_turn_rad(const EvidenceSplit& split);

EffectEvidence camera_misalignment_evidence(const Sensor& sensor, const EvidenceSplit& calibration,
                                            const EvidenceSplit& validation, const FittedParam& fitted);

}  // namespace sb
