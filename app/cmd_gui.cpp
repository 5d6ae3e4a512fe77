// `shearbench gui` (also `shearbench` with no arguments): the interactive workbench. Without a display it
// renders the default view headless under xvfb-run and prints where the PNG is and a short report.
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "app/command.hpp"
#include "app/frontend.hpp"
#include "core/base/free_memory.hpp"
#include "core/base/install_paths.hpp"

namespace sb::app {
namespace {

struct GuiArgs {
  SessionSource open;
  std::string size = "1280x800";
  int profile = 0;
  std::string headless_out;  // empty: default_headless_out (build/, not the repository; installed: the working folder)
  std::string session;
  double autosave_interval_s = 30.0;
  std::string output_folder;  // empty: beside the session file (core/workbench/output_folder)
  std::string residual;
  std::string stats;
  double stats_interval_s = 10.0;
};

bool on_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  if (path == nullptr) return false;
  std::string p(path);
  std::size_t start = 0;
  while (start <= p.size()) {
    const std::size_t end = p.find(':', start);
    const std::string dir = p.substr(start, end == std::string::npos ? std::string::npos : end - start);
    if (!dir.empty() && access((std::filesystem::path(dir) / program).c_str(), X_OK) == 0) return true;
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return false;
}

// Beside the executable in a build folder (build/, not the repository); an installed one's bin/ is not
// the user's to write in, so the working folder there.
std::string default_headless_out(const std::string& self) {
  const std::filesystem::path dir = std::filesystem::path(self).parent_path();
  if (std::filesystem::exists(dir / kBuildHomeFile)) return (dir / "shearbench_headless.png").string();
  return std::filesystem::absolute("shearbench_headless.png").string();
}

// No display: re-run ourselves as `render` under a virtual X server (Mesa llvmpipe).
int run_headless(const GuiArgs& a, const GlobalOptions& g) {
  if (!on_path("xvfb-run")) {
    std::cerr << "shearbench: error: no display (DISPLAY is not set) and xvfb-run is not installed.\n"
                 "  Run it on a desktop, or install xvfb (apt-get install xvfb xauth) to render headless.\n";
    return 1;
  }
  const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
  std::vector<std::string> args = {"xvfb-run", "-a", "-s", "-screen 0 1600x900x24", self};
  if (!g.data_root_flag.empty()) args.insert(args.end(), {"--data", g.data_root_flag});
  if (!g.home_flag.empty()) args.insert(args.end(), {"--home", g.home_flag});
  const std::string out = a.headless_out.empty() ? default_headless_out(self) : a.headless_out;
  args.insert(args.end(), {"render", "--size", "1600x900", "--out", out, "--report"});
  const std::vector<std::string> source = source_arguments(a.open);
  args.insert(args.end(), source.begin(), source.end());
  if (a.profile > 0) args.insert(args.end(), {"--profile", std::to_string(a.profile)});
  if (!a.residual.empty()) args.insert(args.end(), {"--residual", a.residual});
  std::cout << "no display: rendering headless with xvfb-run (Mesa llvmpipe) ...\n" << std::flush;
  std::vector<char*> argv;
  argv.reserve(args.size() + 1);
  for (auto& s : args) argv.push_back(s.data());
  argv.push_back(nullptr);
  execvp("xvfb-run", argv.data());
  std::cerr << "shearbench: error: cannot run xvfb-run\n";
  return 1;
}

int run_gui(const GuiArgs& args, const GlobalOptions& g) {
  GuiArgs a = args;
  if (a.session.empty()) open_report_dataset(a.open, a.residual, g.data_root_flag);  // a report opens its dataset
  if (!ui::display_available()) return run_headless(a, g);
  limit_malloc_arenas(1);  // before any thread starts: see core/base/free_memory.hpp
  const SessionOptions so{a.open, g.data_root_flag};
  FrontendOptions fo;
  std::tie(fo.width, fo.height) = parse_size(a.size);
  fo.keep_work = a.profile == 0;
  fo.autosave_interval_s = a.autosave_interval_s;
  fo.output_folder = a.output_folder;
  Frontend front(so, fo);
  if (a.profile > 0) {
    std::cout << "profile (" << fo.width << "x" << fo.height
              << ", synthetic drag): " << percentiles_line(front.profile_drag(a.profile)) << "\n";
    return 0;
  }
  if (!a.stats.empty()) front.enable_stats(a.stats, a.stats_interval_s);
  front.session().state->start_thread();
  // A session opens on the worker: the window shows the default scene with a progress line meanwhile
  // (it was black for ~3 s); a residual asked for goes on top of it once it is in place.
  const std::string residual = a.residual;
  const auto load_residual = [&front, residual] {
    if (!residual.empty()) front.load_residual(residual);
  };
  if (!a.session.empty()) {
    front.open_session_file(a.session, load_residual);
  } else {
    front.offer_autosave();
    load_residual();
  }
  while (front.frame()) {
  }
  return 0;
}

void add_flags(CLI::App& sub, GuiArgs& a) {
  add_source_options(sub, a.open);
  sub.add_option("--session", a.session, "open a saved session file (JSON)");
  sub.add_option("--autosave-interval", a.autosave_interval_s, "seconds of unsaved changes before an autosave")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  sub.add_option("--size", a.size, "window size")->capture_default_str();
  sub.add_option("--profile", a.profile, "run N frames of a synthetic drag, print frame-time percentiles, exit");
  sub.add_option("--output-folder", a.output_folder,
                 "where P's screenshots and the field export go (default: beside the session file, or "
                 "$XDG_DATA_HOME/shearbench/output when that is in a checkout; never the working folder)");
  sub.add_option("--residual", a.residual, "show a residual analysis (shearbench residual --json)");
  sub.add_option("--stats", a.stats,
                 "append a JSON line of frame-time percentiles, resident memory and live GL objects "
                 "every --stats-interval seconds to this file (tests/cli/soak.py reads it)");
  sub.add_option("--stats-interval", a.stats_interval_s, "seconds per --stats line")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  sub.add_option(
      "--headless-out", a.headless_out,
      "PNG written when there is no display (default: shearbench_headless.png beside the executable in a build "
      "folder, i.e. build/; in the working folder for an installed one)");
}

const Subcommand<GuiArgs> kGuiCommand{"gui", "the interactive workbench (default command); headless without a display",
                                      5, add_flags, run_gui};

}  // namespace
}  // namespace sb::app
