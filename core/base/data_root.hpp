#pragma once
// Where measured data is found: --data, else $SHEARBENCH_DATA, else ../shared/data relative to the
// working directory, else beside the source checkout a build-folder binary takes its files from
// (install_paths.hpp; an installed binary has no such default). Nothing from there is ever copied into
// the repo or installed.
#include <string>

namespace sb {

// `cli_value` is the --data flag (empty when not given). The result is absolute (relative roots are taken
// from the working directory), so joining it to a scene's folder cannot move it; empty when there is no
// root (then resolve_path of a data: path says how to set one).
std::string resolve_data_root(const std::string& cli_value = "");
// Resolves "data:<relative>" against the data root; other paths are returned unchanged (relative ones
// joined to base_dir when base_dir is not empty). A data: path with an empty root throws InputError naming
// --data and SHEARBENCH_DATA.
std::string resolve_path(const std::string& path, const std::string& data_root, const std::string& base_dir);
// A path the user typed (the command line's --dataset / --scene, the workbench's Open field): "data:<rel>"
// through the data root; an absolute path as is; a relative one against `working_dir` when it exists there,
// else against the data root when it exists there ("twin/twin_sphere35" is data:twin/twin_sphere35), else
// against `working_dir` (so the error names the folder the user is in).
std::string resolve_user_path(const std::string& path, const std::string& data_root, const std::string& working_dir);
// The inverse for display: "data:<relative>" when `path` lies inside the data root (so what the user sees
// does not depend on where the data is), else `path` unchanged. resolve_path(data_path(p, r), r, "") names
// the same file as p.
std::string data_path(const std::string& path, const std::string& data_root);
// Throws InputError naming `what` and the searched location when `path` does not exist.
void require_exists(const std::string& path, const std::string& what);

}  // namespace sb
