#include "core/base/free_memory.hpp"

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
