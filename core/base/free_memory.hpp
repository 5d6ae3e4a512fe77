#pragma once
// Gives freed heap memory back to the operating system. glibc keeps the pages a burst of allocations
// freed (a fit loads a dataset, builds SDFs and Jacobians, then drops them), so without this a
// long-running workbench's resident memory stepped up by 15-30 MB with each fit and stayed there (the
// soak of issue 19; a loop of 12 fit jobs: 137 -> 169 MB, with a trim after each 112-150 MB, no trend).
namespace sb {

void return_free_memory_to_os();

}  // namespace sb
