#pragma once
// dome_sway's evidence (core/effects/effect_dome_sway.cpp): the whole array moving under a lateral load.
//
// A dome clamped at its rim bends as a whole when the indenter drags its tip: every pin moves along the slide,
// including those far from the contact. A kernel model of a half-space (and any form error of one) puts its
// field around the contact and nothing where its own field has died away. In the slide frames of a sample (in
// contact, the indenter has slid kSlideTravelPx since first contact) the reading is the mean, over the far markers
// (where the answer's field without the effect is below a tenth of its largest), of the residual along the slide's
// direction in the image (px; > 0: with the slide, as the effect's friction term moves them). Per sample the
// mean over its slide frames; the split's estimate and standard error over samples. It counts only when larger
// than the far markers' own model field along the slide: a kernel's form error (a gain, a width) changes its
// tail by a fraction of itself, while the array's mode is not in a half-space kernel at all.
#include "core/loop/evidence.hpp"

namespace sb {

// Per sample: the far markers' mean residual along the slide (px), NaN without a slide frame.
std::vector<double> far_field_drag_px(const Sensor& sensor, const EvidenceSplit& split);

EffectEvidence dome_sway_evidence(const Sensor& sensor, const EvidenceSplit& calibration,
                                  const EvidenceSplit& validation, const FittedParam& fitted);

}  // namespace sb
