// Models by name: a form and its effects (model_spec.hpp).
#include "core/effects/model_spec.hpp"

#include <algorithm>
#include <stdexcept>

#include "core/effects/effects.hpp"

namespace sb {

std::string ModelSpec::id() const {
  std::string s = form;
  for (const auto& e : effects) s += "+" + e;
  return s;
}

ModelSpec split_model_spec(const std::string& id) {
  std::vector<std::string> parts;
  std::size_t begin = 0;
  for (std::size_t end; (end = id.find('+', begin)) != std::string::npos; begin = end + 1)
    parts.push_back(id.substr(begin, end - begin));
  parts.push_back(id.substr(begin));
  return ModelSpec{parts.front(), {parts.begin() + 1, parts.end()}};
}

ModelSpec parse_model_spec(const std::string& id) {
  ModelSpec spec = split_model_spec(id);
  if (spec.form.empty() || std::find(spec.effects.begin(), spec.effects.end(), "") != spec.effects.end())
    throw std::invalid_argument("model '" + id + "': an empty name between '+' signs");
  default_params(spec.form);  // throws, naming the known forms
  for (std::size_t i = 0; i < spec.effects.size(); ++i) {
    make_effect(spec.effects[i]);  // throws, naming the known effects
    if (std::find(spec.effects.begin(), spec.effects.begin() + i, spec.effects[i]) != spec.effects.begin() + i)
      throw std::invalid_argument("model '" + id + "': effect '" + spec.effects[i] + "' named twice");
  }
  return spec;
}

ParamSet model_spec_params(const std::string& id) {
  const ModelSpec spec = parse_model_spec(id);
  if (spec.effects.empty()) return default_params(spec.form);
  return combined_param_table(default_params(spec.form), spec.effects);
}

std::unique_ptr<ShearModel> make_spec_model(const std::string& id, std::shared_ptr<const Sensor> sensor,
                                            std::shared_ptr<const Indenter> indenter) {
  const ModelSpec spec = parse_model_spec(id);
  auto form = make_model(spec.form, sensor, indenter);
  if (spec.effects.empty()) return form;
  return wrap_with_effects(std::move(form), spec.effects, std::move(sensor), std::move(indenter));
}

}  // namespace sb
