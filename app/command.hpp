#pragma once
// Subcommands register themselves: each app/cmd_<name>.cpp defines one static CommandRegistrar, so
// adding a subcommand touches no shared file. (app/ sources are compiled into the executable itself,
// never into a static library, so the registrars are never dropped by the linker.)
#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

namespace sb::app {

struct GlobalOptions {
  std::string data_root_flag;  // --data (empty: $SHEARBENCH_DATA, then ../shared/data)
  int threads = 0;             // --threads (0: all cores)
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

struct CommandRegistrar {
  CommandRegistrar(std::string name, std::string help, int order, CommandSetup setup) {
    command_registry().push_back({std::move(name), std::move(help), order, std::move(setup)});
  }
};

}  // namespace sb::app
