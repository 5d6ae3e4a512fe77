#include "core/base/free_memory.hpp"

// <cstdlib> pulls in <features.h>, which defines __GLIBC__: without a libc header first the test below was
// false and both functions compiled to nothing (found in the hour soak of 2026-11-25, third run).
#include <cstdio>
#include <cstdlib>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace sb {

void return_free_memory_to_os() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

void limit_malloc_arenas(int arenas) {
#if defined(__GLIBC__)
  mallopt(M_ARENA_MAX, arenas);
#else
  (void)arenas;
#endif
}

ResidentParts resident_parts() {
  ResidentParts r;
  std::FILE* f = std::fopen("/proc/self/status", "r");
  if (f == nullptr) return r;
  char line[256];
  while (std::fgets(line, sizeof line, f) != nullptr) {
    std::sscanf(line, "RssAnon: %ld", &r.anon_kb);
    std::sscanf(line, "RssFile: %ld", &r.file_kb);
  }
  std::fclose(f);
  return r;
}

}  // namespace sb
