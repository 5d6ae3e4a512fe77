#pragma once
// skin_indentation's evidence (core/effects/effect_skin_indentation.cpp): the convergence towards the image
// centre.
//
// Where an indenter presses a dome's skin inward, the pins move towards the dome's centre, and a camera inside
// the dome sees them move towards its principal point. A kernel model's field is the surface's in-plane
// displacement, and its form error about a press of an axisymmetric indenter is symmetric about the contact
// centre: it moves the indented markers towards (or away from) the contact, not the image centre. In the press
// frames of a sample, over the markers inside the indenter (penetration h > 0), the residual is regressed on
// h u_pp and h u_cc together, u_pp the unit vector from the marker towards the principal point and u_cc towards
// the contact centre: the reading is u_pp's coefficient (px per mm of penetration, > 0: towards the centre).
// A contact at the image centre makes the two regressors one (their correlation above kMaxCollinearity): the
// sample tells nothing and is skipped. An orthographic camera sees no normal motion: no reading.
#include "core/loop/evidence.hpp"

namespace sb {

// Per sample: the convergence towards the principal point, px per metre of penetration; NaN when the sample has
// no indented marker off the collinear case.
std::vector<double> centre_convergence_px_per_m(const Sensor& sensor, const EvidenceSplit& split);

EffectEvidence skin_indentation_evidence(const Sensor& sensor, const EvidenceSplit& calibration,
                                         const EvidenceSplit& validation, const FittedParam& fitted);

}  // namespace sb
