#pragma once
// What a path typed into the workbench's Open field (or chosen from its list) is: a tsd/1 dataset folder, a
// scene (scenes/*.json) or a session file. Paths resolve as on the command line (core/base/data_root:
// "data:..." through the data root, a relative path in the working folder, else in the data root), so
// "twin/twin_sphere35", "data:twin/twin_sphere35" and "scenes/press_cow.json" all open.
#include <string>
#include <vector>

namespace sb {

enum class OpenKind { kDataset, kScene, kSession };

struct OpenTarget {
  OpenKind kind = OpenKind::kScene;
  std::string path;   // resolved: the dataset folder, the scene or the session file
  std::string typed;  // as the user wrote it (kept for the session file: "data:..." stays portable)
};

// Throws InputError naming the resolved path when it does not exist or is none of the three.
OpenTarget classify_open_target(const std::string& typed, const std::string& data_root, const std::string& working_dir);

// What the Open list offers: the scenes in `scenes_dir` (as given: "scenes/press_cow.json") and the datasets one
// or two folders below the data root ("data:twin/twin_sphere35"), sorted, scenes first.
std::vector<std::string> open_suggestions(const std::string& data_root, const std::string& scenes_dir);

// The last opened paths, newest first, without duplicates, at most `capacity` (kept for this run only: the
// workbench writes no file but the session and its autosave).
class RecentPaths {
 public:
  explicit RecentPaths(std::size_t capacity = 8) : capacity_(capacity) {}
  void add(const std::string& path);
  const std::vector<std::string>& paths() const { return paths_; }

 private:
  std::size_t capacity_;
  std::vector<std::string> paths_;
};

}  // namespace sb
