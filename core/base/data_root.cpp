#include "core/base/data_root.hpp"

#include <cstdlib>
#include <filesystem>

#include "core/base/error.hpp"
#include "core/base/install_paths.hpp"

namespace fs = std::filesystem;

namespace sb {

namespace {

constexpr const char* kNoDataRoot =
    "no data root: give --data DIR or set SHEARBENCH_DATA=DIR (a tsd/1 data root such as ../shared/data; "
    "there is none beside the working folder or the source checkout)";

// The root as an absolute, normalised path: a relative root would be resolved again against whatever
// folder a path inside it is later joined to (a scene's folder turned ../shared/data/meshes/cow.obj into
// scenes/../shared/data/meshes/cow.obj).
std::string absolute_root(const fs::path& root) {
  std::error_code ec;
  const fs::path abs = fs::absolute(root, ec);
  return (ec ? root : abs).lexically_normal().string();
}

}  // namespace

std::string resolve_data_root(const std::string& cli_value) {
  if (!cli_value.empty()) return absolute_root(cli_value);
  if (const char* env = std::getenv("SHEARBENCH_DATA"); env && *env) return absolute_root(env);
  if (fs::exists("../shared/data")) return absolute_root("../shared/data");
  // Running from build/ or elsewhere: the layout puts shared/ beside the source checkout the binary's files
  // come from. An installed binary's home is share/shearbench, not a checkout: no default there.
  std::string home;
  try {
    home = home_dir();
  } catch (const InputError&) {
    return "";
  }
  const fs::path beside_checkout = fs::path(home) / ".." / "shared" / "data";
  if (is_source_checkout(home) && fs::exists(beside_checkout)) return absolute_root(beside_checkout);
  return "";
}

std::string resolve_path(const std::string& path, const std::string& data_root, const std::string& base_dir) {
  constexpr std::string_view kDataPrefix = "data:";
  if (path.rfind(kDataPrefix, 0) == 0) {
    if (data_root.empty()) throw InputError(path, kNoDataRoot);
    return (fs::path(data_root) / path.substr(kDataPrefix.size())).string();
  }
  const fs::path p(path);
  if (p.is_absolute() || base_dir.empty()) return path;
  return (fs::path(base_dir) / p).string();
}

std::string resolve_user_path(const std::string& path, const std::string& data_root, const std::string& working_dir) {
  if (path.empty() || path.rfind("data:", 0) == 0 || fs::path(path).is_absolute())
    return resolve_path(path, data_root, working_dir);
  std::error_code ec;
  const fs::path here = working_dir.empty() ? fs::path(path) : fs::path(working_dir) / path;
  if (fs::exists(here, ec)) return here.string();
  const fs::path in_root = fs::path(data_root) / path;
  if (!data_root.empty() && fs::exists(in_root, ec)) return in_root.string();
  return here.string();
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
    throw InputError(path, what +
                               " not found (a path under the data root is written data:twin/twin_sphere35; "
                               "data root: set --data or SHEARBENCH_DATA; default ../shared/data beside the "
                               "working folder or the source checkout)");
}

}  // namespace sb
