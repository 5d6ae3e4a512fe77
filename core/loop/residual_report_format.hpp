#pragma once
// The number formats and look-ups the residual report's JSON, Markdown and plots share (residual_report*.cpp only).
#include <string>
#include <vector>

#include "core/base/format.hpp"
#include "core/loop/residual.hpp"

namespace sb::report_format {

// Tables: three decimals, a dash where a value is missing.
inline std::string f3(double v) { return format_number(v, "%.3f", "–"); }
// Axis labels and parameter values: three significant digits.
inline std::string g3(double v) { return format_number(v, "%.3g", "nan"); }
inline double rmse_of(const EffectFit& f) { return f.validation.overall.result().rmse_px; }

// The effect search's fit of the effect set `ids`, or nullptr; points into `r`.
inline const EffectFit* fit_of(const ResidualReport& r, const std::vector<std::string>& ids) {
  auto it = r.effects.fits.find(effect_set_key(ids));
  return it == r.effects.fits.end() ? nullptr : &it->second;
}

}  // namespace sb::report_format
