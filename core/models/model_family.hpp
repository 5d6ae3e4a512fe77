#pragma once
// One descriptor per model family: everything the rest of the code knows about a family of shear models, written
// once in the family's own file (hydroshear_family.cpp, fots_family.cpp, tacsl_family.cpp) and registered once in
// model_families(). Calibration asks it for the fit stages and the precision rule, the residual loop for the
// model-form corrections and the held parameters, the workbench and the CLI for ids, labels and panels.
// How a family is added: docs/howto/add-a-model.md.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/base/params.hpp"
#include "core/models/any_batch.hpp"
#include "core/models/model.hpp"

namespace sb {

// One stage of a model's calibration procedure (core/calibration/fit.hpp runs them).
struct FitStage {
  std::string name{};
  std::vector<std::string> params{};            // names in the model's ParamSet
  std::vector<std::string> motions{};           // samples used
  bool rescale = false;                         // fit the shape with a free per-fit scale
  std::vector<std::string> fallback_motions{};  // used (and reported) when no sample has `motions`
};

// How one form's models are built: a single-sensor ShearModel (`id` is what it reports) and a batch of sensors.
// family_factories.hpp makes both from one constructor of the form's batched kernel.
struct FormFactories {
  std::function<std::unique_ptr<ShearModel>(const std::string& id, std::shared_ptr<const Sensor> sensor,
                                            std::shared_ptr<const Indenter> indenter, const ParamSet& params)>
      make_model;
  std::function<std::unique_ptr<AnyBatch>(const std::shared_ptr<const Sensor>& sensor,
                                          const std::shared_ptr<const Indenter>& indenter, int slots,
                                          const ParamSet& params)>
      make_batch;
};

// Whether a form is a published model or a model-form correction of its family's base form (ours, not published:
// the residual loop tries these against the base, docs/effects.md).
enum class FormKind { kPublished, kCorrection };

// One model form: a model id with its parameter table, fit stages and factories.
struct ModelForm {
  std::string id;     // "tacsl-normalized": --model, JSON keys of parameter tables, session files
  std::string label;  // "TacSL (normalized)": panel titles and legends
  FormKind kind = FormKind::kPublished;
  std::vector<ParamSpec> params;  // the default table (names are the JSON keys)
  std::vector<FitStage> fit_stages;
  // Added to the joint refinement when a fit also fits the image scale (FitOptions::fit_px_scale).
  std::vector<std::string> px_scale_params = {};
  FormFactories make;
};

struct ModelFamily {
  std::string id;     // "tacsl": the session file's and the gui's key for the form shown in the family's panel
  std::string label;  // "TacSL": the family's group in the Parameters section
  std::vector<ModelForm> forms;  // forms.front() is the family's base form
  // The residual loop refits a selected correction with these fitted only in their first stage (FitOptions::hold).
  std::vector<std::string> hold = {};
  // A switch that runs the model in single precision; a fit sets it to 0 (float sums move by ~1e-7 of the field,
  // noise far above the solver's parameter tolerance). Empty: the family has none.
  std::string single_precision_switch = {};

  const ModelForm& base() const { return forms.front(); }
  // The model-form corrections of the base form, in table order.
  std::vector<std::string> correction_ids() const;
  std::vector<std::string> form_ids() const;
};

// Every registered family, in display order (HydroShear, FOTS, TacSL).
const std::vector<ModelFamily>& model_families();
// The family of that id. Throws std::invalid_argument with a did-you-mean for an unknown id.
const ModelFamily& model_family(const std::string& family_id);
// The family that has the form `form_id`. Throws std::invalid_argument with a did-you-mean for an unknown form.
const ModelFamily& family_of_form(const std::string& form_id);
// The form of that id. Throws as family_of_form does.
const ModelForm& model_form(const std::string& form_id);
// The form of that id, or nullptr (no error) when it is not one, e.g. a form followed by effects.
const ModelForm* find_model_form(const std::string& form_id);
const ModelFamily* find_model_family_of_form(const std::string& form_id);

// The registered families, each defined in its own file.
ModelFamily hydroshear_family();
ModelFamily fots_family();
ModelFamily tacsl_family();

}  // namespace sb
