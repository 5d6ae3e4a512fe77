#include "core/base/display_path.hpp"

#include <filesystem>

#include "core/base/data_root.hpp"

namespace sb {

namespace fs = std::filesystem;

std::string display_path(const std::string& path, const std::string& data_root, const std::string& working_dir) {
  if (path.empty()) return path;
  if (std::string d = data_path(path, data_root); d.rfind("data:", 0) == 0) return d;
  if (fs::path(path).is_relative()) return path;
  std::error_code ec;
  const fs::path cwd = working_dir.empty() ? fs::current_path(ec) : fs::path(working_dir);
  if (ec) return path;
  const fs::path base = fs::weakly_canonical(fs::absolute(cwd, ec), ec);
  const fs::path p = fs::weakly_canonical(path, ec);
  if (ec) return path;
  const fs::path rel = p.lexically_relative(base);
  if (rel.empty() || rel == "." || *rel.begin() == "..") return path;
  return rel.generic_string();
}

}  // namespace sb
