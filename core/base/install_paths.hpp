#pragma once
// Where shearbench finds its own files: scenes/, assets/params, the indenter meshes in assets/, docs/. That
// folder is its "home":
//   1. the --home flag (set_home_flag), else $SHEARBENCH_HOME;
//   2. installed (<prefix>/bin/shearbench): <prefix>/share/shearbench;
//   3. in a build folder: the source tree named in the file `shearbench-home` beside the executable
//      (CMake writes it; `cmake --install` does not copy it).
// Nothing is compiled in: a moved or packaged executable finds its own files or says where it looked,
// never the checkout it was built from.
#include <string>

namespace sb {

// The file a build folder holds beside its executables, naming the source tree (place 3).
inline constexpr const char* kBuildHomeFile = "shearbench-home";
// The folder a home is recognised by (every command starts from a parameter set).
inline constexpr const char* kHomeMarker = "assets/params";

// The home of an executable at `exe_path`, given the --home flag and $SHEARBENCH_HOME (empty: not set).
// An override is returned as given (made absolute); otherwise the first place above that holds
// assets/params. Empty when none does. Looks only at the file system, so a test can lay out a prefix.
std::string find_home(const std::string& exe_path, const std::string& flag, const std::string& env);
// The running executable's home (/proc/self/exe, the --home flag, $SHEARBENCH_HOME). Throws InputError
// naming the places it looked, and both ways to set it, when there is none or an override holds no
// assets/params.
std::string home_dir();

// A shared library's own path (libshearbench.so): home_dir() then looks from there instead of from the
// executable that loaded it (python3). Set once, when the library is loaded (lib/library_home.cpp).
void set_home_anchor(const std::string& path);
// The anchor for a library at `library_path`: the path itself, or under a multiarch folder
// (<prefix>/lib/x86_64-linux-gnu/libshearbench.so) the same name one level up (<prefix>/lib/...), so that
// find_home's <dir>/../share/shearbench is the prefix's.
std::string library_home_anchor(const std::string& library_path);

// The --home flag (empty: not given); set once while parsing the command line.
void set_home_flag(const std::string& dir);
// The path of the running executable ("" when /proc/self/exe cannot be read).
std::string executable_path();
// Whether `home` is a source checkout rather than an installed share/shearbench (it has CMakeLists.txt
// and core/): only then is ../shared/data beside it a default data root.
bool is_source_checkout(const std::string& home);

}  // namespace sb
