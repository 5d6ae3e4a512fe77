#pragma once
// The residual loop's report (ResidualReport, residual.hpp) in its three forms: JSON, Markdown and PNG plots.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/loop/residual.hpp"

namespace sb {

nlohmann::ordered_json residual_to_json(const ResidualReport& r);
// Writes the PNG plots into `dir` named "<stem>_*.png" and returns their file names (not paths).
std::vector<std::string> write_residual_plots(const ResidualReport& r, const std::string& dir, const std::string& stem);
std::string residual_to_markdown(const ResidualReport& r, const std::vector<std::string>& plots);

// The form's parameters a candidate's joint refit `f` moved by more than 5 % from the form's fit: what the effect
// let the form stop doing (value before -> after).
nlohmann::ordered_json base_shifts_json(const ResidualReport& r, const EffectFit& f);

}  // namespace sb
