// shearbench: entry point. Parses the global flags, dispatches to the registered subcommands, and turns
// bad input into one clear line (file:line:col: what) instead of a crash.
#include <algorithm>
#include <iostream>
#include <map>

#include "app/build_info.hpp"
#include "app/command.hpp"
#include "app/interrupt.hpp"
#include "core/base/closest_name.hpp"
#include "core/base/error.hpp"
#include "core/base/install_paths.hpp"
#include "core/base/progress.hpp"
#include "core/base/reproducible.hpp"

namespace {

// The word left over where a command was expected (`shearbench evalute ...`): the first argument CLI11 could
// not place when no command was recognised; "" when a command was, or the leftover is a flag.
std::string misspelt_command(const CLI::App& cli) {
  for (const CLI::App* sub : cli.get_subcommands([](const CLI::App*) { return true; }))
    if (sub->parsed()) return "";
  const std::vector<std::string> extra = cli.remaining();
  if (extra.empty() || extra.front().empty() || extra.front().front() == '-') return "";
  return extra.front();
}

}  // namespace

int main(int argc, char** argv) {
  using namespace sb::app;
  CLI::App cli{"shearbench: a workbench for tactile shear models (HydroShear, FOTS, TacSL) against GelSight data"};
  cli.set_version_flag("--version",
                       std::string("shearbench ") + SHEARBENCH_VERSION + " (commit " + sb::app::build_commit() + ")");
  GlobalOptions global;
  cli.add_option("--data", global.data_root_flag,
                 "data root (default: $SHEARBENCH_DATA, else ../shared/data beside the working folder or the "
                 "source checkout)");
  cli.add_option("--home", global.home_flag,
                 "folder with shearbench's scenes/ and assets/params (default: $SHEARBENCH_HOME, else "
                 "../share/shearbench beside the executable)");
  cli.add_option("--threads", global.threads, "worker threads (0: all cores)");
  cli.add_flag("-q,--quiet", global.quiet, "print less");
  cli.add_flag_callback(
      "--reproducible", [] { sb::set_timings_in_outputs(false); },
      "leave wall-clock times out of every output file (bit-identical reruns)");
  cli.require_subcommand(0, 1);
  // The global options are accepted after the subcommand too (`shearbench gui --data DIR`): a subcommand
  // hands the options it does not know to its parent (CLI11 fallthrough, inherited by every subcommand).
  cli.fallthrough();
  cli.footer(
      "With no subcommand: opens the workbench (`gui`) on the default scene; "
      "without a display it renders the default scene headless.");

  auto& registry = command_registry();
  std::sort(registry.begin(), registry.end(), [](auto& a, auto& b) { return a.order < b.order; });
  std::map<CLI::App*, std::function<int()>> runners;
  for (auto& c : registry) {
    CLI::App* sub = cli.add_subcommand(c.name, c.help);
    runners[sub] = c.setup(*sub, global);
  }

  try {
    cli.parse(argc, argv);
  } catch (const CLI::ExtrasError& e) {
    if (const std::string typed = misspelt_command(cli); !typed.empty()) {
      std::vector<std::string> names;
      names.reserve(registry.size());
      for (const auto& c : registry) names.push_back(c.name);
      std::cerr << "shearbench: error: unknown command '" << typed << "'" << sb::did_you_mean(typed, names)
                << "; `shearbench --help` lists the commands\n";
      return 2;
    }
    return cli.exit(e) == 0 ? 0 : 2;
  } catch (const CLI::ParseError& e) {
    // A bad flag is bad input: exit 2 like every other (CLI11's own codes, 100-120, were undocumented); --help
    // and --version stay 0.
    return cli.exit(e) == 0 ? 0 : 2;
  }
  sb::set_home_flag(global.home_flag);

  try {
    for (auto& [sub, run] : runners)
      if (sub->parsed()) return run();
    // No subcommand: the workbench when it is built, help otherwise.
    for (auto& [sub, run] : runners)
      if (sub->get_name() == "gui") return run();
    std::cout << cli.help();
    return 0;
  } catch (const sb::InputError& e) {
    std::cerr << "shearbench: error: " << e.what() << "\n";
    return 2;
  } catch (const sb::Cancelled& e) {
    std::cerr << "shearbench: " << e.what() << "; no output was written\n";
    return sb::app::kExitCancelled;
  } catch (const std::exception& e) {
    std::cerr << "shearbench: error: " << e.what() << "\n";
    return 1;
  }
}
