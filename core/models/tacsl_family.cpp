// TacSL's family (model_family.hpp): the raw penalty shear and its normalised form.
#include "core/models/family_factories.hpp"
#include "core/models/tacsl.hpp"

namespace sb {

namespace {

// TacSL: gain_px * k_n is one factor, so k_n stays at 1 and the gain is fitted on presses; the tangential law
// (k_t, mu) on slides. Normalised, it outputs gain * unit direction: the gain sets every magnitude, k_t / k_n
// turns the direction between the normal push and the tangential drag; mu only acts where the drag saturates and
// is close to unidentifiable from directions (a test fit from its own data put it at the bound with 0.04 px RMSE
// left), so it keeps its default.
std::vector<FitStage> tacsl_stages(bool normalized) {
  if (normalized)
    return {{.name = "gain", .params = {"gain_px"}, .motions = {"dilation", "shear"}},
            {.name = "direction", .params = {"kt"}, .motions = {"shear"}}};
  return {{.name = "normal-gain", .params = {"gain_px"}, .motions = {"dilation"}},
          {.name = "tangential", .params = {"kt", "mu"}, .motions = {"shear"}}};
}

FormFactories tacsl_factories(bool normalized) {
  return factories_of<TacslBatch>(
      [normalized](const std::shared_ptr<const Sensor>& sensor, const std::shared_ptr<const Indenter>& indenter,
                   int slots,
                   const ParamSet& params) { return TacslBatch(normalized, sensor, indenter, slots, params); });
}

}  // namespace

ModelFamily tacsl_family() {
  return {
      .id = "tacsl",
      .label = "TacSL",
      .forms = {{.id = "tacsl",
                 .label = "TacSL",
                 .params = tacsl_param_specs(false),
                 .fit_stages = tacsl_stages(false),
                 .make = tacsl_factories(false)},
                {.id = "tacsl-normalized",
                 .label = "TacSL (normalized)",
                 .params = tacsl_param_specs(true),
                 .fit_stages = tacsl_stages(true),
                 .make = tacsl_factories(true)}},
  };
}

}  // namespace sb
