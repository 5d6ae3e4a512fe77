#pragma once
// A model's parameters as a struct of its own, each field bound by a member pointer to the one ParamSpec that
// describes it (name, unit, default, range): the code reads `k.lambda_s`, so a misspelt name does not compile,
// while the ParamSet built from the same table keeps the names for the sliders, JSON and CLI flags. A bool field
// is a switch: a checkbox in the workbench, 0 or 1 in JSON and on the command line.
#include <stdexcept>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "core/base/params.hpp"

namespace sb {

template <typename Values>
struct ParamField {
  ParamField(ParamSpec s, double Values::*m) : spec(std::move(s)), member(m) {}
  ParamField(ParamSpec s, bool Values::*m) : spec(std::move(s)), member(m) { spec.is_switch = true; }
  ParamSpec spec;
  std::variant<double Values::*, bool Values::*> member;
};

template <typename Values>
using ParamFields = std::vector<ParamField<Values>>;

// The table's specs in its order: what a ParamSet of these parameters is built from.
template <typename Values>
std::vector<ParamSpec> specs_of(const ParamFields<Values>& fields) {
  std::vector<ParamSpec> specs;
  specs.reserve(fields.size());
  for (const ParamField<Values>& f : fields) specs.push_back(f.spec);
  return specs;
}

// Sets each field of `values` whose parameter `p` holds (a switch is on from 0.5); the others keep their value,
// so a variant's absent term stays off. A parameter of `p` that no field describes throws std::invalid_argument:
// the set was not built from this table.
template <typename Values>
void read_params(const ParamFields<Values>& fields, const ParamSet& p, Values& values) {
  for (std::size_t i = 0; i < p.size(); ++i) {
    const ParamField<Values>* field = nullptr;
    for (const ParamField<Values>& f : fields)
      if (f.spec.name == p.specs()[i].name) field = &f;
    if (field == nullptr) throw std::invalid_argument("parameter '" + p.specs()[i].name + "' is not in the table");
    if (const auto* d = std::get_if<double Values::*>(&field->member))
      values.*(*d) = p[i];
    else
      values.*std::get<bool Values::*>(field->member) = p[i] >= 0.5;
  }
}

template <typename Values>
Values read_params(const ParamFields<Values>& fields, const ParamSet& p) {
  Values values{};
  read_params(fields, p, values);
  return values;
}

}  // namespace sb
