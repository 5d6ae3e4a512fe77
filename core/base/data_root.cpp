#include "core/base/data_root.hpp"

#include <cstdlib>
#include <filesystem>

#include "core/base/error.hpp"

namespace fs = std::filesystem;

namespace sb {

std::string resolve_data_root(const std::string& cli_value) {
  if (!cli_value.empty()) return cli_value;
  if (const char* env = std::getenv("SHEARBENCH_DATA"); env && *env) return env;
  if (fs::exists("../shared/data")) return "../shared/data";
  // Running from build/ or elsewhere: the layout puts shared/ beside the repository.
  const fs::path beside_source = fs::path(SHEARBENCH_SOURCE_DIR) / ".." / "shared" / "data";
  if (fs::exists(beside_source)) return fs::weakly_canonical(beside_source).string();
  return "../shared/data";
}

std::string resolve_path(const std::string& path, const std::string& data_root, const std::string& base_dir) {
  constexpr std::string_view kDataPrefix = "data:";
  if (path.rfind(kDataPrefix, 0) == 0) return (fs::path(data_root) / path.substr(kDataPrefix.size())).string();
  const fs::path p(path);
  if (p.is_absolute() || base_dir.empty()) return path;
  return (fs::path(base_dir) / p).string();
}

std::string data_path(const std::string& path, const std::string& data_root) {
  if (path.empty() || data_root.empty() || path.rfind("data:", 0) == 0) return path;
  std::error_code ec;
  const fs::path root = fs::weakly_canonical(fs::absolute(data_root, ec), ec);
  const fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
  if (ec) return path;
  const fs::path rel = p.lexically_relative(root);
  if (rel.empty() || rel == "." || *rel.begin() == "..") return path;
  return "data:" + rel.generic_string();
}

void require_exists(const std::string& path, const std::string& what) {
  if (!fs::exists(path))
    throw InputError(path, what + " not found (data root: set --data or SHEARBENCH_DATA; default ../shared/data)");
}

}  // namespace sb
