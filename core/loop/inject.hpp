#pragma once
// Known effects put into measured data, undeclared: how the residual loop is checked where its answer is
// known (tests/test_residual_hard.cpp, `shearbench inject`). The effect changes the measurement the way it
// would have: creep filters each marker's measured series through the standard linear solid, lens distortion
// maps the measured displacement through the lens, subsurface markers smooth the measured field.
#include <map>
#include <random>
#include <string>
#include <vector>

#include "core/calibration/fit.hpp"

namespace sb {

// Repeats the deepest frame (pose and measured field) `frames` times, with fresh Gaussian tracking noise of
// `noise_px` per component on the repeats: a held press of a quasi-static recording (the FE twins are not
// held, and creep needs a hold to show).
void insert_hold(const Sensor& sensor, int frames, double noise_px, std::mt19937_64* rng, FitSample* s);

// Applies `effect` at `params` (its own parameter names; the rest at their defaults) to the measured series
// of `s`, frame by frame. Throws std::invalid_argument for an unknown effect or parameter.
void inject_effect(const Sensor& sensor, const std::string& effect, const std::map<std::string, double>& params,
                   FitSample* s);

// The rest grid as a camera with `effect` records it: a lens images the printed grid bent too (each rest position
// through the k1 lens, lens_distort_px; k2 is not applied), while p_EM stays where the markers physically are.
// Any other effect leaves the rest grid as it is. The injected fields (inject_effect) are about the unbent rest.
std::vector<Vec2> recorded_rest_px(const Camera& camera, const std::string& effect,
                                   const std::map<std::string, double>& params, std::vector<Vec2> rest_px);

}  // namespace sb
