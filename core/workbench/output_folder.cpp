#include "core/workbench/output_folder.hpp"

#include <cstdlib>
#include <filesystem>

namespace sb {

namespace fs = std::filesystem;

bool inside_git_checkout(const std::string& dir) {
  std::error_code ec;
  fs::path p = fs::absolute(dir, ec).lexically_normal();
  if (ec) return false;
  for (; !p.empty(); p = p.parent_path()) {
    if (fs::exists(p / ".git", ec)) return true;
    if (p == p.root_path()) break;
  }
  return false;
}

std::string default_user_output_folder() {
  if (const char* x = std::getenv("XDG_DATA_HOME"); x && *x) return (fs::path(x) / "shearbench" / "output").string();
  if (const char* h = std::getenv("HOME"); h && *h)
    return (fs::path(h) / ".local" / "share" / "shearbench" / "output").string();
  return (fs::temp_directory_path() / "shearbench_output").string();
}

std::string output_folder(const std::string& chosen, const std::string& session_path, const std::string& user_folder,
                          const std::function<bool(const std::string&)>& in_checkout) {
  const fs::path beside = session_path.empty() ? fs::path() : fs::path(session_path).parent_path();
  if (!chosen.empty()) {
    if (fs::path(chosen).is_absolute() || beside.empty() || !beside.is_absolute()) {
      if (fs::path(chosen).is_absolute()) return chosen;
      return (fs::path(user_folder) / chosen).string();  // never the working folder
    }
    return (beside / chosen).string();
  }
  if (!beside.empty() && beside.is_absolute() && !in_checkout(beside.string())) return beside.string();
  return user_folder;
}

std::string output_path(const std::string& path, const std::string& folder) {
  if (path.empty() || fs::path(path).is_absolute()) return path;
  return (fs::path(folder) / path).string();
}

}  // namespace sb
