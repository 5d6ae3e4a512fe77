#pragma once
// Keeping a long-running process's heap from holding on to what bursts of work freed.
namespace sb {

// Gives freed heap memory back to the operating system. glibc keeps the pages a burst of allocations
// freed (a fit loads a dataset, builds SDFs and Jacobians, then drops them), so without this a
// long-running workbench's resident memory stepped up by 15-30 MB with each fit and stayed there (the
// soak of issue 19; a loop of 12 fit jobs: 137 -> 169 MB, with a trim after each 112-150 MB, no trend).
void return_free_memory_to_os();

// Caps the number of glibc malloc arenas (call before threads start). Every thread that allocates gets
// an arena of its own up to 8 per core, and each keeps the high-water mark of what ran on it: in the
// workbench the fit thread, the physics thread and TBB's workers. A walk of fits (docs/reliability.md,
// "Memory over a fit"): resident memory levels off after 3-4 fits at 340-347 MB with glibc's default,
// 326-341 MB with 2 arenas, 322 MB flat with 1. The workbench takes 1: what a thread frees goes back to the
// one heap that malloc_trim returns to the system, and the cost is small because glibc's per-thread cache
// serves small allocations without the lock (a twin_sphere35 fit, the CLI with MALLOC_ARENA_MAX=1:
// 10.1 -> 10.7 s, +6 %, on the shared 2 cores). No-op off glibc.
void limit_malloc_arenas(int arenas);

}  // namespace sb
