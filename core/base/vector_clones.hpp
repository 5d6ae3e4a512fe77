#pragma once
// SB_VECTOR_CLONES before a function compiles it three times, for AVX-512 (x86-64-v4), AVX2/FMA
// (x86-64-v3) and the baseline, and picks one at load time (GCC target_clones), so the binary stays
// portable. The AVX-512 clone took the HydroShear workload from 9.3 to 8.0 ms on this project's 2-core
// AMD EPYC machine (docs/performance.md); a CPU without it runs the AVX2 or baseline clone. Only code
// inlined into the function gets the wider vectors: keep the hot loops inside it. Other compilers get
// the baseline.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define SB_VECTOR_CLONES __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define SB_VECTOR_CLONES
#endif

// SB_IVDEP before a loop tells GCC its iterations are independent (#pragma GCC ivdep), so it vectorises
// without a runtime alias check; other compilers (clang warns on GCC's pragma) get nothing.
#if defined(__GNUC__) && !defined(__clang__)
#define SB_IVDEP _Pragma("GCC ivdep")
#else
#define SB_IVDEP
#endif
