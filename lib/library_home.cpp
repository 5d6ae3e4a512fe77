// libshearbench.so finds shearbench's own files (assets/params, scenes/, docs/) from where the library is, not
// from the program that loaded it (python3, a consumer): <prefix>/lib[/<multiarch>]/libshearbench.so ->
// <prefix>/share/shearbench, or in a build folder the source tree named in shearbench-home beside it. Compiled into
// the shared library only; the executable keeps finding its home from itself.
#include <dlfcn.h>

#include <filesystem>

#include "core/base/install_paths.hpp"

namespace {

struct LibraryHome {
  LibraryHome() {
    Dl_info info{};
    if (dladdr(reinterpret_cast<void*>(&anchor), &info) == 0 || info.dli_fname == nullptr) return;
    std::filesystem::path lib = info.dli_fname;
    // find_home looks in <dir>/../share/shearbench: under a multiarch folder (lib/x86_64-linux-gnu) that is
    // one level further up.
    const std::filesystem::path dir = lib.parent_path();
    if (dir.filename() != "lib" && dir.parent_path().filename() == "lib") lib = dir.parent_path() / lib.filename();
    sb::set_home_anchor(lib.string());
  }
  static void anchor() {}
};

const LibraryHome library_home;

}  // namespace
