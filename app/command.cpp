#include "app/command.hpp"

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

}  // namespace sb::app
