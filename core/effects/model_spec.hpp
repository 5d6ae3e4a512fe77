#pragma once
// A model by name: a model form (core/models' model_ids(): a published model or one of HydroShear's
// variants) followed by catalogued effects, written "<form>+<effect>+<effect>", e.g.
// "hydroshear-contact+viscoelastic_creep". The residual loop's answer is such a model (docs/effects.md);
// every command that takes --model, and the workbench, build it through make_spec_model.
#include <memory>
#include <string>
#include <vector>

#include "core/base/params.hpp"
#include "core/models/model.hpp"

namespace sb {

struct ModelSpec {
  std::string form;                  // a model_ids() entry
  std::vector<std::string> effects;  // effect_ids() entries, in the order they apply
  // "<form>+<effect>+..." (the form alone without effects).
  std::string id() const;
};

// Splits on '+'. Throws std::invalid_argument naming the part for an unknown form or effect, an empty
// part or an effect named twice.
ModelSpec parse_model_spec(const std::string& id);
// The parts as written, unchecked and without building anything: for naming a model already built (a panel's
// title every frame), where parse_model_spec's checks would make every effect once more.
ModelSpec split_model_spec(const std::string& id);
// The default table of the model: the form's table, then each effect's as "<effect>.<name>".
ParamSet model_spec_params(const std::string& id);
// The model itself (the form alone when there are no effects). Throws as parse_model_spec does.
std::unique_ptr<ShearModel> make_spec_model(const std::string& id, std::shared_ptr<const Sensor> sensor,
                                            std::shared_ptr<const Indenter> indenter);

}  // namespace sb
