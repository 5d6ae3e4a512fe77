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

HeapUse heap_use() {
  HeapUse h;
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
  const struct mallinfo2 m = mallinfo2();
  h.in_use_kb = static_cast<long>((m.uordblks + m.hblkhd) / 1024);
  h.free_kb = static_cast<long>(m.fordblks / 1024);
#endif
  return h;
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
