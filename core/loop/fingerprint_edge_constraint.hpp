#pragma once
// edge_constraint's evidence (core/effects/effect_edge_constraint.cpp): the field held back at the pad's sides.
//
// A pad clamped at its walls moves less within a boundary layer of its sides than the same field in its
// interior. Per sample, the gain of the measured field against the answer's field without the effect,
// g = sum meas.pred / sum |pred|^2, on the markers within one boundary length l of a side (the effect's length)
// and on the rest; the reading is 1 - g_edge / g_interior (> 0: held back at the sides, the effect's strength
// times the mean of exp(-dist / l) there). A half-space model's form error about a contact is fixed to the
// contact, not to the pad; but a finite pad's sides respond unlike a half-space's too (a free side moves more),
// so this evidence shows a restraint at the sides, clamp or finite pad alike, and its sign must be the fit's.
#include "core/loop/evidence.hpp"

namespace sb {

// Per sample: the strength s read over its moving frames, NaN when either half has no field.
std::vector<double> edge_hold_back(const Sensor& sensor, const EvidenceSplit& split, double length_m);

EffectEvidence edge_constraint_evidence(const Sensor& sensor, const EvidenceSplit& calibration,
                                        const EvidenceSplit& validation, const FittedParam& fitted);

}  // namespace sb
