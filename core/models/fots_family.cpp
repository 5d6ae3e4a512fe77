// FOTS's family (model_family.hpp): the original repository's model and the HydroShear paper's re-centred one.
#include <tuple>

#include "core/models/family_factories.hpp"
#include "core/models/fots.hpp"

namespace sb {

namespace {

// FOTS's family: one kernel rate per load type, as its marker_calib.py does. The original has no gains (h is
// the depth, the shear is the indenter's motion in px); the re-implementation fits each load's gain with its
// rate. The twist clip only acts beyond 50 deg.
std::vector<FitStage> fots_stages(bool reimpl) {
  std::vector<FitStage> stages;
  for (const auto& [load, rate, gain] :
       {std::tuple{"dilation", "lambda_d", "kappa_d"}, std::tuple{"shear", "lambda_s", "kappa_s"},
        std::tuple{"twist", "lambda_t", "kappa_t"}}) {
    FitStage s{.name = load, .params = {rate}, .motions = {load}};
    if (reimpl) s.params.emplace_back(gain);
    stages.push_back(std::move(s));
  }
  return stages;
}

FormFactories fots_factories(FotsVariant variant) {
  return factories_of<FotsBatch>(
      [variant](const std::shared_ptr<const Sensor>& sensor, const std::shared_ptr<const Indenter>& indenter, int slots,
                const ParamSet& params) { return FotsBatch(variant, sensor, indenter, slots, params); });
}

}  // namespace

ModelFamily fots_family() {
  return {
      .id = "fots",
      .label = "FOTS",
      .forms = {{.id = "fots",
                 .label = "FOTS",
                 .params = fots_param_specs(),
                 .fit_stages = fots_stages(false),
                 .px_scale_params = {"px_per_mm"},  // the re-implementation's px/m gains are stage parameters
                 .make = fots_factories(FotsVariant::kOriginal)},
                {.id = "fots-reimpl",
                 .label = "FOTS (reimpl)",
                 .params = fots_reimpl_param_specs(),
                 .fit_stages = fots_stages(true),
                 .make = fots_factories(FotsVariant::kReimpl)}},
  };
}

}  // namespace sb
