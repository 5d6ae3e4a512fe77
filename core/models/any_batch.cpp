#include "core/models/any_batch.hpp"

#include <stdexcept>

#include "core/models/model_family.hpp"

namespace sb {

bool has_batch(const std::string& model_id) { return find_model_form(model_id) != nullptr; }

std::unique_ptr<AnyBatch> make_batch(const std::string& model, const std::shared_ptr<const Sensor>& sensor,
                                     const std::shared_ptr<const Indenter>& indenter, int slots,
                                     const ParamSet& params) {
  const ModelForm* form = find_model_form(model);
  if (form == nullptr) throw std::invalid_argument("unknown model '" + model + "' (" + model_ids_text(", ") + ")");
  return form->make.make_batch(sensor, indenter, slots, params);
}

}  // namespace sb
