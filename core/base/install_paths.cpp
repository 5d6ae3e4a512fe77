#include "core/base/install_paths.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "core/base/error.hpp"

namespace fs = std::filesystem;

namespace sb {

namespace {

std::string& home_flag() {
  static std::string flag;
  return flag;
}

std::string& home_anchor() {
  static std::string anchor;
  return anchor;
}

bool holds_marker(const fs::path& dir) {
  std::error_code ec;
  return !dir.empty() && fs::is_directory(dir / kHomeMarker, ec);
}

std::string normal(const fs::path& p) {
  std::error_code ec;
  const fs::path abs = fs::absolute(p, ec);
  return (ec ? p : abs).lexically_normal().string();
}

// The first line of <exe dir>/shearbench-home: the source tree of a build folder ("" when absent).
fs::path build_tree_home(const fs::path& exe_dir) {
  std::ifstream in(exe_dir / kBuildHomeFile);
  std::string line;
  if (!in || !std::getline(in, line)) return {};
  while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
  return line;
}

}  // namespace

std::string find_home(const std::string& exe_path, const std::string& flag, const std::string& env) {
  if (!flag.empty()) return normal(flag);
  if (!env.empty()) return normal(env);
  if (exe_path.empty()) return {};
  std::error_code ec;
  // Through symlinks (/usr/local/bin/shearbench -> /opt/shearbench/bin/shearbench): the real file's prefix.
  const fs::path exe_dir = fs::weakly_canonical(fs::absolute(exe_path, ec), ec).parent_path();
  if (const fs::path installed = exe_dir.parent_path() / "share" / "shearbench"; holds_marker(installed))
    return normal(installed);
  if (const fs::path source = build_tree_home(exe_dir); holds_marker(source)) return normal(source);
  return {};
}

std::string executable_path() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string() : exe.string();
}

std::string home_dir() {
  const char* env = std::getenv("SHEARBENCH_HOME");
  const std::string env_value = env ? env : "";
  const std::string exe = home_anchor().empty() ? executable_path() : home_anchor();
  std::string home = find_home(exe, home_flag(), env_value);
  const std::string how = "set SHEARBENCH_HOME or pass --home to the folder holding scenes/ and assets/params";
  if (home.empty()) {
    const fs::path dir = fs::path(exe).parent_path();
    throw InputError(exe.empty() ? "shearbench" : exe, "shearbench's own files not found: looked for " +
                                                           (dir.parent_path() / "share/shearbench").string() +
                                                           " (installed) and " + (dir / kBuildHomeFile).string() +
                                                           " (a build folder); " + how);
  }
  if (!holds_marker(home))
    throw InputError(home, std::string("not a shearbench home (no ") + kHomeMarker + " in it; from " +
                               (home_flag().empty() ? "SHEARBENCH_HOME" : "--home") + "); " + how);
  return home;
}

void set_home_flag(const std::string& dir) { home_flag() = dir; }
void set_home_anchor(const std::string& path) { home_anchor() = path; }

std::string library_home_anchor(const std::string& library_path) {
  const fs::path lib = library_path, dir = lib.parent_path();
  if (dir.filename() != "lib" && dir.parent_path().filename() == "lib")
    return (dir.parent_path() / lib.filename()).string();
  return library_path;
}

bool is_source_checkout(const std::string& home) {
  std::error_code ec;
  return !home.empty() && fs::is_regular_file(fs::path(home) / "CMakeLists.txt", ec) &&
         fs::is_directory(fs::path(home) / "core", ec);
}

}  // namespace sb
