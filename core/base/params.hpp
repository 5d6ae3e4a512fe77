#pragma once
// Each tunable parameter is described once (name, unit, default, range); sliders, JSON I/O and CLI
// flags are all generated from these tables.
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace sb {

struct ParamSpec {
  std::string name;  // identifier: json key, CLI flag suffix, slider label
  std::string unit;  // "m^-2", "px/m", "" for dimensionless
  double default_value;
  double min;
  double max;
  std::string help;
  bool log_scale = false;  // sliders and fits work on log(value)
  // The value changes only the field a model computes from its state, never the state a step carries to
  // the next (a kernel's width or gain, not friction): a fit's finite differences over it replay only the
  // scored frames from the state before them (core/calibration/fit.cpp).
  bool field_only = false;
  // An on/off choice stored as 0 or 1 (a bool in the model's typed parameters: core/base/typed_params.hpp): a
  // checkbox in the workbench, never a fitted value.
  bool is_switch = false;
};

class ParamSet {
 public:
  ParamSet() = default;
  explicit ParamSet(std::vector<ParamSpec> specs);

  const std::vector<ParamSpec>& specs() const { return specs_; }
  const std::vector<double>& values() const { return values_; }
  std::size_t size() const { return specs_.size(); }
  double get(std::string_view name) const;  // throws std::out_of_range for an unknown name
  double operator[](std::size_t i) const { return values_[i]; }
  // Throws std::invalid_argument when the value is non-finite or outside [min, max].
  void set(std::string_view name, double value);
  void set(std::size_t i, double value);
  void reset_to_defaults();
  int index_of(std::string_view name) const;  // -1 when absent

  nlohmann::json to_json() const;
  // Reads the keys present in `j`; unknown keys and out-of-range values throw InputError(where).
  void update_from_json(const nlohmann::json& j, const std::string& where);

 private:
  std::vector<ParamSpec> specs_;
  std::vector<double> values_;
};

}  // namespace sb
