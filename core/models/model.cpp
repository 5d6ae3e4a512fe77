// Model ids, default parameter tables and single-sensor ShearModel instances, as the family registry
// (model_family.hpp) describes them.
#include "core/models/model.hpp"

#include "core/models/model_family.hpp"

namespace sb {

const std::vector<std::string>& model_ids() {
  // The published forms of every family first, then the corrections: "--model all" and the help texts list them so.
  static const std::vector<std::string> ids = [] {
    std::vector<std::string> out;
    for (const FormKind kind : {FormKind::kPublished, FormKind::kCorrection})
      for (const ModelFamily& family : model_families())
        for (const ModelForm& form : family.forms)
          if (form.kind == kind) out.push_back(form.id);
    return out;
  }();
  return ids;
}

std::string model_ids_text(const std::string& separator) {
  std::string text;
  for (const std::string& m : model_ids()) text += (text.empty() ? "" : separator) + m;
  return text;
}

ParamSet default_params(const std::string& id) { return ParamSet(model_form(id).params); }

std::unique_ptr<ShearModel> make_model(const std::string& id, std::shared_ptr<const Sensor> sensor,
                                       std::shared_ptr<const Indenter> indenter) {
  const ModelForm& form = model_form(id);
  return form.make.make_model(id, std::move(sensor), std::move(indenter), ParamSet(form.params));
}

}  // namespace sb
