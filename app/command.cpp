#include "app/command.hpp"

#include "core/base/error.hpp"
#include "core/effects/model_spec.hpp"

namespace sb::app {

std::vector<CommandInfo>& command_registry() {
  static std::vector<CommandInfo> registry;
  return registry;
}

CLI::Option* add_dataset_flag(CLI::App& sub, std::string& dataset) {
  return sub.add_option("--dataset", dataset, "dataset folder (data:... resolves through the data root)")->required();
}

CLI::Option* add_params_flag(CLI::App& sub, std::string& params, const std::string& what) {
  return sub.add_option("--params", params, what + ": {model: {name: value}} or a flat {name: value}");
}

CLI::Option* add_param_set_flag(CLI::App& sub, std::string& param_set) {
  return sub.add_option("--param-set", param_set,
                        "parameter set to start from: a name in assets/params (see `shearbench params`) or a file; "
                        "'published' = the authors' values (default: twin_sphere35 for the GelSight Mini, the set "
                        "fitted for the sensor otherwise, e.g. tactip_shear)");
}

void require_model(const std::string& model_id, const std::string& flag) {
  try {
    (void)parse_model_spec(model_id);
  } catch (const std::invalid_argument& e) {
    throw InputError(flag, e.what());
  }
}

}  // namespace sb::app
