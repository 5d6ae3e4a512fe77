// The family registry (model_family.hpp): each family registered once, here.
#include "core/models/model_family.hpp"

#include <stdexcept>

#include "core/base/closest_name.hpp"

namespace sb {

std::vector<std::string> ModelFamily::correction_ids() const {
  std::vector<std::string> ids;
  for (const ModelForm& f : forms)
    if (f.kind == FormKind::kCorrection) ids.push_back(f.id);
  return ids;
}

std::vector<std::string> ModelFamily::form_ids() const {
  std::vector<std::string> ids;
  ids.reserve(forms.size());
  for (const ModelForm& f : forms) ids.push_back(f.id);
  return ids;
}

const std::vector<ModelFamily>& model_families() {
  static const std::vector<ModelFamily> families = {hydroshear_family(), fots_family(), tacsl_family()};
  return families;
}

const ModelFamily& model_family(const std::string& family_id) {
  std::vector<std::string> ids;
  for (const ModelFamily& f : model_families()) {
    if (f.id == family_id) return f;
    ids.push_back(f.id);
  }
  std::string known;
  for (const std::string& id : ids) known += (known.empty() ? "" : ", ") + id;
  throw std::invalid_argument("unknown model family '" + family_id + "'" + did_you_mean(family_id, ids) +
                              " (known: " + known + ")");
}

const ModelFamily* find_model_family_of_form(const std::string& form_id) {
  for (const ModelFamily& family : model_families())
    for (const ModelForm& form : family.forms)
      if (form.id == form_id) return &family;
  return nullptr;
}

const ModelForm* find_model_form(const std::string& form_id) {
  for (const ModelFamily& family : model_families())
    for (const ModelForm& form : family.forms)
      if (form.id == form_id) return &form;
  return nullptr;
}

const ModelFamily& family_of_form(const std::string& form_id) {
  if (const ModelFamily* f = find_model_family_of_form(form_id)) return *f;
  throw std::invalid_argument("unknown model id '" + form_id + "'" + did_you_mean(form_id, model_ids()) +
                              " (known: " + model_ids_text(", ") + ")");
}

const ModelForm& model_form(const std::string& form_id) {
  if (const ModelForm* f = find_model_form(form_id)) return *f;
  family_of_form(form_id);  // throws, naming the known forms
  throw std::logic_error("unreachable");
}

}  // namespace sb
