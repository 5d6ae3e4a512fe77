#pragma once
// spread_saturation's evidence (core/effects/effect_spread_saturation.cpp): the spread under the contact stops
// growing with depth while the field away from it does not.
//
// The effect replaces each marker's depth in the model's dilation by h0 tanh(h / h0): it takes away from the
// field where the indenter is deep, under and around the contact, and leaves the far field. So in presses the
// near part of the field loses gain with depth faster than the far part: with the per-part slopes of
// fingerprint_load_stiffening.hpp (beta of 1/g against depth), the reading is beta_near - beta_far per sample
// (> 0 for saturation). A uniform stiffening moves both alike and reads 0; a model whose near field grows with
// depth faster than the gel's reads the same sign, which this evidence cannot tell from saturation: the sign
// must be the fit's (a positive gain), and both splits must show it.
#include "core/loop/evidence.hpp"

namespace sb {

EffectEvidence spread_saturation_evidence(const Sensor& sensor, const EvidenceSplit& calibration,
                                          const EvidenceSplit& validation, const FittedParam& fitted);

}  // namespace sb
