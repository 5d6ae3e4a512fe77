#pragma once
// One-line and short text summaries the `render` and `gui` commands print.
#include <string>
#include <vector>

#include "core/workbench/app_state.hpp"

namespace sb::app {

// p50 / p90 / p99 / max of frame times, one line.
std::string percentiles_line(std::vector<double> ms);
// Short text report: per-model step time and field magnitudes at the current step.
std::string text_report(const AppSnapshot& snap);

}  // namespace sb::app
