// core/base/free_memory: the heap a burst of work freed goes back to the system. Measured as the process's
// RssAnon (/proc/self/status), glibc only: elsewhere (and under AddressSanitizer, which owns malloc) the
// functions do nothing and the test says so.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <vector>

#include "core/base/free_memory.hpp"
#include "tests/asan_detect.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_free_memory {

TEST_CASE("return_free_memory_to_os hands a freed burst of small blocks back", "[base][memory]") {
#if defined(SB_TEST_ASAN) || !defined(__GLIBC__)
  WARN("skipped: needs glibc's allocator (the release pass on Linux runs this test)");
#else
  // 64 MB in 4 KB blocks (below glibc's mmap threshold: they live in the heap, each carved from its top in
  // turn); all but the last are freed, so the last pins the top and the heap cannot shrink by itself. glibc
  // keeps those 64 MB resident until malloc_trim hands the free pages back.
  constexpr std::size_t kBlock = 4096, kBlocks = 16384;
  constexpr long kBurstKb = kBlock * kBlocks / 1024;
  std::vector<char*> blocks;
  blocks.reserve(kBlocks);
  for (std::size_t i = 0; i < kBlocks; ++i) {
    blocks.push_back(static_cast<char*>(std::malloc(kBlock)));
    for (std::size_t b = 0; b < kBlock; b += 512) blocks.back()[b] = 1;  // touch every page
  }
  char* pin = blocks.back();
  blocks.pop_back();
  const long in_use_with_burst = sb::heap_use().in_use_kb;
  for (char* b : blocks) std::free(b);
  // The heap's own count sees the burst go: every block but the pin, each a 4096-byte chunk plus its header
  // (4112 bytes), so at least the burst less one block, less 1 kB for the rounding of both readings.
  const long freed_kb = in_use_with_burst - sb::heap_use().in_use_kb;
  CHECK(freed_kb >= kBurstKb - static_cast<long>(kBlock / 1024) - 1);
  const long before = sb::resident_parts().anon_kb;
  REQUIRE(before > 0);
  sb::return_free_memory_to_os();
  const long after = sb::resident_parts().anon_kb;
  std::free(pin);
  INFO("RssAnon " << before << " kB -> " << after << " kB after the trim (burst " << kBurstKb << " kB)");
  // At least half the burst comes back (what stays is the pages glibc's chunk headers share with live data).
  CHECK(before - after > kBurstKb / 2);
#endif
}

}  // namespace test_free_memory
