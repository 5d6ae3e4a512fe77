// libshearbench.so finds shearbench's own files (assets/params, scenes/, docs/) from where the library is, not
// from the program that loaded it (python3, a consumer): <prefix>/lib[/<multiarch>]/libshearbench.so ->
// <prefix>/share/shearbench, or in a build folder the source tree named in shearbench-home beside it. Compiled into
// the shared library only; the executable keeps finding its home from itself.
#include <dlfcn.h>

#include "core/base/install_paths.hpp"

namespace {

struct LibraryHome {
  LibraryHome() {
    Dl_info info{};
    if (dladdr(reinterpret_cast<void*>(&anchor), &info) == 0 || info.dli_fname == nullptr) return;
    sb::set_home_anchor(sb::library_home_anchor(info.dli_fname));
  }
  static void anchor() {}
};

const LibraryHome library_home;

}  // namespace
