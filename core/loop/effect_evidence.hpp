#pragma once
// Which effects of the loop's answer are found (docs/effects.md, "Evidence: found or a correction of unshown
// cause"): for each selected effect, its evidence (evidence.hpp; one reader per effect, fingerprint_<effect>.hpp)
// read on both splits from the measurement and the answer's field without that effect, at the answer's
// parameters. This step labels the answer; it changes neither the selection nor the fit.
#include <string>
#include <vector>

#include "core/base/params.hpp"
#include "core/calibration/fit.hpp"
#include "core/loop/evidence.hpp"

namespace sb {

// The catalogued effects that have an evidence reader (every one: tests/test_effect_evidence.cpp checks the
// catalogue), and whether one needs each marker's penetration per frame.
std::vector<std::string> evidenced_effects();
bool evidence_needs_marker_depth(const std::string& effect_id);

// A split as the readers see it, without a model's field (pred_px empty): the fingerprints' view, the recorded
// penetration and tilt per frame, each marker's penetration when `marker_depth`, and the split's tracker noise.
EvidenceSplit evidence_split(const Sensor& sensor, const std::vector<FitSample>& samples, bool marker_depth);

// The evidence of `effect_id` on two splits whose pred_px is the answer's field without it; `fitted` gives the
// answer's values of the effect's own parameters. Throws std::invalid_argument for an effect without a reader.
EffectEvidence read_evidence(const std::string& effect_id, const Sensor& sensor, const EvidenceSplit& calibration,
                             const EvidenceSplit& validation, const FittedParam& fitted);

// The evidence of every effect of the answer `form` + `selected` at `params` (the answer's table): for each, the
// answer without it is run on both splits (every sample) and read_evidence applied. In the order of `selected`.
std::vector<EffectEvidence> answer_evidence(const std::shared_ptr<const Sensor>& sensor, const std::string& form,
                                            const std::vector<std::string>& selected, const ParamSet& params,
                                            const std::vector<FitSample>& calibration,
                                            const std::vector<FitSample>& validation);

}  // namespace sb
