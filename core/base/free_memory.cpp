#include "core/base/free_memory.hpp"

// <cstdlib> pulls in <features.h>, which defines __GLIBC__: without a libc header first the test below was
// false and both functions compiled to nothing (found in the hour soak of 2026-11-25, third run).
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

}  // namespace sb
