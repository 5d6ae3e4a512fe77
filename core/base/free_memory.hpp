#pragma once
// Keeping a long-running process's heap from holding on to what bursts of work freed.
namespace sb {

// Gives freed heap memory back to the operating system. glibc keeps the pages a burst of allocations
// freed (a fit loads a dataset, builds SDFs and Jacobians, then drops them), so without this a
// long-running workbench's resident memory stepped up with each fit and stayed there (the hour soak of
// docs/reliability.md). A test checks that a freed 64 MB burst comes back (tests/test_free_memory.cpp).
void return_free_memory_to_os();

// Caps the number of glibc malloc arenas (call before threads start). Every thread that allocates gets
// an arena of its own up to 8 per core, and each keeps the high-water mark of what ran on it: in the
// workbench the fit thread, the physics thread and TBB's workers. The workbench takes 1: what any thread
// frees goes back to the one heap that return_free_memory_to_os trims, and glibc's per-thread cache serves
// small allocations without the lock (a twin_sphere35 fit with MALLOC_ARENA_MAX=1: 10.1 -> 10.7 s, +6 %,
// on the shared 2 cores). With the trim and the cap acting (both compiled to nothing before 12b95eb), the
// hour soak's workbench held 281 MB at minute 5 where it held 361 MB (docs/reliability.md). No-op off glibc.
void limit_malloc_arenas(int arenas);

// This process's resident memory in two parts (kB, from RssAnon and RssFile of /proc/self/status; -1 each
// when unreadable): the heap (what a trim can give back, what grows with a leak) and file-backed pages
// (code and mapped data, touched the first time a fit or a mesh needs them).
struct ResidentParts {
  long anon_kb = -1;
  long file_kb = -1;
};
ResidentParts resident_parts();

// What the malloc heap holds (kB, glibc's mallinfo2; -1 each off glibc): bytes in live allocations (heap chunks
// and mmapped blocks) and bytes free inside the heap that a trim has not returned. A step in RssAnon that
// stays after a trim is either live objects (in_use rises) or fragmentation (free rises).
struct HeapUse {
  long in_use_kb = -1;
  long free_kb = -1;
};
HeapUse heap_use();

}  // namespace sb
