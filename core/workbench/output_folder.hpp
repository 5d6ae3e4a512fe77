#pragma once
// Where the files the workbench writes go (P's screenshots, the field export's folder): one folder, chosen by
// the user (`gui --output-folder`), else beside the session file, else a per-user folder. Never the working
// folder when that is a checkout: P twice wrote two PNGs into the repository.
#include <functional>
#include <string>

namespace sb {

// True when `dir` (made absolute) or a folder above it holds .git: a source checkout.
bool inside_git_checkout(const std::string& dir);

// $XDG_DATA_HOME/shearbench/output, else ~/.local/share/shearbench/output (the temporary folder's
// shearbench_output when HOME is unset).
std::string default_user_output_folder();

// `chosen` when not empty (a relative one is taken beside the session file, not in the working folder); else the
// session file's folder unless `in_checkout` says it is inside a checkout; else `user_folder`. Pure but for the
// predicate.
std::string output_folder(const std::string& chosen, const std::string& session_path, const std::string& user_folder,
                          const std::function<bool(const std::string&)>& in_checkout);

// `path` as the workbench writes it: an absolute path as is, a relative one inside `folder`.
std::string output_path(const std::string& path, const std::string& folder);

}  // namespace sb
