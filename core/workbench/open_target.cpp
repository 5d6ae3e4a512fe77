#include "core/workbench/open_target.hpp"

#include <algorithm>
#include <filesystem>

#include "core/base/data_root.hpp"
#include "core/base/error.hpp"
#include "core/workbench/session_file.hpp"

namespace sb {

namespace fs = std::filesystem;

OpenTarget classify_open_target(const std::string& typed, const std::string& data_root,
                                const std::string& working_dir) {
  if (typed.empty()) throw InputError("Open", "no path: type a dataset folder, a scene (.json) or a session file");
  OpenTarget t;
  t.typed = typed;
  t.path = resolve_user_path(typed, data_root, working_dir);
  std::error_code ec;
  if (!fs::exists(t.path, ec))
    throw InputError(t.path, "not found (paths under the data root are written data:twin/twin_sphere35; data root " +
                                 data_root + ")");
  if (fs::is_directory(t.path, ec)) {
    if (!fs::exists(fs::path(t.path) / "dataset.json", ec))
      throw InputError(t.path, "is a folder without dataset.json: not a tsd/1 dataset");
    t.kind = OpenKind::kDataset;
    return t;
  }
  if (fs::path(t.path).filename() == "dataset.json") {
    t.kind = OpenKind::kDataset;
    t.path = fs::path(t.path).parent_path().string();
    return t;
  }
  if (is_session_file(t.path)) {
    t.kind = OpenKind::kSession;
    return t;
  }
  if (fs::path(t.path).extension() != ".json")
    throw InputError(t.path, "is not a dataset folder, a scene (.json) or a shearbench session file");
  t.kind = OpenKind::kScene;
  return t;
}

namespace {

// Datasets (folders with dataset.json) at depth 1 or 2 below the root, as "data:<relative>".
void add_datasets(const fs::path& root, std::vector<std::string>& out) {
  std::error_code ec;
  for (const auto& a : fs::directory_iterator(root, ec)) {
    if (!a.is_directory(ec)) continue;
    if (fs::exists(a.path() / "dataset.json", ec)) out.push_back("data:" + a.path().filename().string());
    for (const auto& b : fs::directory_iterator(a.path(), ec))
      if (b.is_directory(ec) && fs::exists(b.path() / "dataset.json", ec))
        out.push_back("data:" + a.path().filename().string() + "/" + b.path().filename().string());
  }
}

}  // namespace

std::vector<std::string> open_suggestions(const std::string& data_root, const std::string& scenes_dir) {
  std::vector<std::string> scenes, datasets;
  std::error_code ec;
  if (!scenes_dir.empty())
    for (const auto& e : fs::directory_iterator(scenes_dir, ec))
      if (e.is_regular_file(ec) && e.path().extension() == ".json")
        scenes.push_back((fs::path(scenes_dir) / e.path().filename()).string());
  if (!data_root.empty()) add_datasets(data_root, datasets);
  std::sort(scenes.begin(), scenes.end());
  std::sort(datasets.begin(), datasets.end());
  scenes.insert(scenes.end(), datasets.begin(), datasets.end());
  return scenes;
}

void RecentPaths::add(const std::string& path) {
  if (path.empty()) return;
  paths_.erase(std::remove(paths_.begin(), paths_.end(), path), paths_.end());
  paths_.insert(paths_.begin(), path);
  if (paths_.size() > capacity_) paths_.resize(capacity_);
}

}  // namespace sb
