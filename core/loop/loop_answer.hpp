#pragma once
// The residual loop's answer for a sensor: what `shearbench residual --model hydroshear` ended with on the dataset a
// parameter set was fitted on (its form and effects, at the parameters the loop fitted), read from that run's
// report among shearbench's own (docs/residuals/<run>/residual.json in its home). The workbench shows it beside
// HydroShear when it opens a real recording of that sensor.
#include <optional>
#include <string>

#include "core/calibration/param_sets.hpp"
#include "core/loop/residual_view.hpp"

namespace sb {

struct LoopAnswer {
  ResidualSummary summary;  // summary.file: the residual.json it was read from
};

// The report under `reports_dir` (one folder per run, each with a residual.json) whose dataset is the one `set`
// was fitted on (provenance "dataset", its last path component) and whose base model is HydroShear, when that run
// selected anything; nullopt when none is (a missing folder, a set with no dataset, a run that selected nothing). A
// report of an injected variant ("twin_sphere35+viscoelastic_creep") is not the set's dataset. A report that cannot
// be read is skipped: a broken file must not keep a dataset from opening (its name is in `skipped`, if given).
std::optional<LoopAnswer> find_loop_answer(const NamedParamSet& set, const std::string& reports_dir,
                                           std::string* skipped = nullptr);

// `find_loop_answer` over shearbench's home (docs/residuals); nullopt when there is no home. The shipped reports do
// not change while shearbench runs: each set's answer is read once per process (every sample opened of a real
// recording asks again, and reading every report takes a few tenths of a second).
std::optional<LoopAnswer> find_shipped_loop_answer(const NamedParamSet& set, std::string* skipped = nullptr);

}  // namespace sb
