#pragma once
// load_stiffening's evidence (core/effects/effect_load_stiffening.cpp): the stiffness rising with depth at a
// fixed contact shape.
//
// The effect scales the whole field by 1 / (1 + beta delta): every marker by the same factor at a given depth.
// In the press frames of a sample (in contact, the contact has not travelled) the measured field's gain against
// the answer's field without the effect, g = sum meas.pred / sum |pred|^2, is read on two parts of the field that
// keep their place in the contact's shape as it grows: the near part (markers with |pred| >= half the frame's
// largest) and the far part (a tenth to a half). 1/g = a + b delta is fitted per part, beta = b / a. A gel that
// stiffens lowers both alike; a contact model whose field changes shape with depth unlike the gel's (a contact
// radius growing at another rate, a near field the model lacks) moves one part's gain and not the other's. The
// reading is the whole field's beta (both parts together); it counts only where the near and far betas agree
// within the agreement ratio with one sign (each read where its per-sample scatter resolves it).
#include "core/loop/evidence.hpp"

namespace sb {

// Per sample: beta (1/m) of the whole field, of its near and of its far part; NaN where the sample has fewer than
// three press frames over a depth range, or a part has no gain to read.
struct DepthGainSlopes {
  std::vector<double> all, near, far;
};
DepthGainSlopes depth_gain_slopes(const EvidenceSplit& split);

EffectEvidence load_stiffening_evidence(const Sensor& sensor, const EvidenceSplit& calibration,
                                        const EvidenceSplit& validation, const FittedParam& fitted);

}  // namespace sb
