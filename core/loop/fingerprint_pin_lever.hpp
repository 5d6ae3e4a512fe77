#pragma once
// pin_lever's evidence (core/effects/effect_pin_lever.cpp): the indented pins' outward shift that does not grow
// with depth.
//
// A pin that follows the skin's turn moves its tip by -g L (n_new - n_rest): once a marker is under the
// indenter its skin has the indenter's face normal, so the shift is set at first touch and stays as the press
// deepens (outward from the contact, growing with the marker's distance from the contact centre). A kernel
// model's field, and its form error, grow from zero with the penetration. In the press frames of a sample, over
// the markers inside the indenter (penetration h > 0), the residual's component outward from the contact centre
// is regressed on rho and rho h (rho the marker's distance from the contact centre, px): the reading is the
// depth-independent coefficient (px of shift per px of distance, > 0 outward), the lever's share at h -> 0.
// A sample needs at least three press frames: within one frame h also varies across the contact (deep at its
// centre, 0 at its edge), so a single image cannot tell the lever from a form error at the contact's edge.
#include "core/loop/evidence.hpp"

namespace sb {

// Per sample: the outward shift per px of distance at zero penetration; NaN without indented markers at two depths.
std::vector<double> lever_shift(const Sensor& sensor, const EvidenceSplit& split);

EffectEvidence pin_lever_evidence(const Sensor& sensor, const EvidenceSplit& calibration,
                                  const EvidenceSplit& validation, const FittedParam& fitted);

}  // namespace sb
