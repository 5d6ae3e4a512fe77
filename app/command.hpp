#pragma once
// Subcommands register themselves: each app/cmd_<name>.cpp holds its flags in one struct, a function that
// declares them and one that runs it, and defines one static Subcommand<Args>, so adding a subcommand
// touches no shared file. (app/ sources are compiled into the executable itself, never into a static
// library, so the registrations are never dropped by the linker.)
#include <CLI/CLI.hpp>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace sb::app {

struct GlobalOptions {
  std::string data_root_flag;  // --data (empty: $SHEARBENCH_DATA, then ../shared/data; core/base/data_root.hpp)
  std::string home_flag;  // --home (empty: $SHEARBENCH_HOME, then beside the executable; core/base/install_paths.hpp)
  int threads = 0;        // --threads (0: all cores)
  bool quiet = false;
};

// Adds the subcommand's options to `sub` and returns the function that runs it (exit code).
using CommandSetup = std::function<std::function<int()>(CLI::App& sub, const GlobalOptions& global)>;

struct CommandInfo {
  std::string name;
  std::string help;
  int order;  // position in --help
  CommandSetup setup;
};

std::vector<CommandInfo>& command_registry();

// One subcommand: `Args` holds its flags (defaults in the struct), `add_flags` declares them on the
// CLI11 subcommand, `run` runs it once they are parsed and returns the exit code.
template <class Args>
struct Subcommand {
  using AddFlags = void (*)(CLI::App& sub, Args& args);
  using Run = int (*)(const Args& args, const GlobalOptions& global);
  Subcommand(std::string name, std::string help, int order, AddFlags add_flags, Run run) {
    command_registry().push_back(
        {std::move(name), std::move(help), order, [add_flags, run](CLI::App& sub, const GlobalOptions& global) {
           auto args = std::make_shared<Args>();
           add_flags(sub, *args);
           return std::function<int()>([args, run, &global] { return run(*args, global); });
         }});
  }
};

// Flags several subcommands share, described once.
// --dataset DIR (required): a tsd/1 folder; data:... resolves through the data root.
CLI::Option* add_dataset_flag(CLI::App& sub, std::string& dataset);
// --params FILE: parameter JSON keyed by model id, or flat for one model.
CLI::Option* add_params_flag(CLI::App& sub, std::string& params, const std::string& what = "parameter JSON");
// --param-set NAME|FILE: the parameter set a command starts from (assets/params; default twin_sphere35,
// `published` for the authors' values); --params applies on top.
CLI::Option* add_param_set_flag(CLI::App& sub, std::string& param_set);
// Throws InputError naming `flag` when `model_id` is not a model by name (a form, or a form with effects:
// core/effects/model_spec.hpp), so a typo exits 2 before any work.
void require_model(const std::string& model_id, const std::string& flag = "--model");

}  // namespace sb::app
