#pragma once
// gravity_preload's evidence (core/effects/effect_gravity_preload.cpp): a fixed shear at the contact from the
// first touch, whatever the motion.
//
// A constant tangential load adds the same shear g around the contact in every frame in contact, presses
// included. A press of an axisymmetric indenter gives a field symmetric about the contact, and so does a contact
// model's error of it: at the contact centre its mean is zero. In the press frames of a sample, the residual
// weighted by exp(-|m - c|^2 / (2 w^2)) about the contact centre c (w the effect's width) is averaged (a vector);
// the reading is the component (x or y) more significant over samples (px), as tracker_bias's.
#include "core/loop/evidence.hpp"

namespace sb {

// Per sample: the weighted mean residual at the contact over its press frames (px).
std::vector<Vec2> contact_shear_px(const Sensor& sensor, const EvidenceSplit& split, double width_m);

EffectEvidence gravity_preload_evidence(const Sensor& sensor, const EvidenceSplit& calibration,
                                        const EvidenceSplit& validation, const FittedParam& fitted);

}  // namespace sb
