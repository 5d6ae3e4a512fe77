#pragma once
// Paths as the workbench shows them: what is on screen (and so in screenshots and render baselines)
// should not depend on where this machine keeps the data or the repository.
#include <string>

namespace sb {

// "data:<relative>" when `path` lies inside the data root; else relative to `working_dir` when inside
// it (the repository root, usually); else `path` unchanged. The result names the same file from
// `working_dir` (resolve_path undoes "data:"). `working_dir` empty: the current directory.
std::string display_path(const std::string& path, const std::string& data_root, const std::string& working_dir = "");

}  // namespace sb
