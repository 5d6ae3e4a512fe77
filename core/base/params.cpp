#include "core/base/params.hpp"

#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "core/base/error.hpp"

namespace sb {

ParamSet::ParamSet(std::vector<ParamSpec> specs) : specs_(std::move(specs)) { reset_to_defaults(); }

void ParamSet::reset_to_defaults() {
  values_.clear();
  for (const auto& s : specs_) values_.push_back(s.default_value);
}

int ParamSet::index_of(std::string_view name) const {
  for (std::size_t i = 0; i < specs_.size(); ++i)
    if (specs_[i].name == name) return static_cast<int>(i);
  return -1;
}

double ParamSet::get(std::string_view name) const {
  const int i = index_of(name);
  if (i < 0) throw std::out_of_range("unknown parameter '" + std::string(name) + "'");
  return values_[i];
}

void ParamSet::set(std::size_t i, double value) {
  const ParamSpec& s = specs_.at(i);
  if (!std::isfinite(value) || value < s.min || value > s.max) {
    std::ostringstream m;
    m << "parameter '" << s.name << "' = " << value << " is outside [" << s.min << ", " << s.max << "]";
    throw std::invalid_argument(m.str());
  }
  values_[i] = value;
}

void ParamSet::set(std::string_view name, double value) {
  const int i = index_of(name);
  if (i < 0) throw std::out_of_range("unknown parameter '" + std::string(name) + "'");
  set(static_cast<std::size_t>(i), value);
}

nlohmann::json ParamSet::to_json() const {
  nlohmann::json j = nlohmann::json::object();
  for (std::size_t i = 0; i < specs_.size(); ++i) j[specs_[i].name] = values_[i];
  return j;
}

void ParamSet::update_from_json(const nlohmann::json& j, const std::string& where) {
  if (!j.is_object()) throw InputError(where, "parameters must be a JSON object of name: number");
  for (const auto& [key, v] : j.items()) {
    const int i = index_of(key);
    if (i < 0) throw InputError(where, "unknown parameter '" + key + "'");
    if (!v.is_number()) throw InputError(where, "parameter '" + key + "' is not a number");
    try {
      set(static_cast<std::size_t>(i), v.get<double>());
    } catch (const std::invalid_argument& e) {
      throw InputError(where, e.what());
    }
  }
}

}  // namespace sb
