// Every input a fuzzer crashed on (tests/data/fuzz/<target>/<name>), replayed through the same code as
// the fuzz target (fuzz/fuzz_inputs.hpp): each must now load or be refused with an InputError.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "fuzz/fuzz_inputs.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_fuzz_regressions {

namespace {

namespace fs = std::filesystem;
using OneInput = void (*)(const std::uint8_t*, std::size_t);

std::size_t replay(const std::string& target, OneInput one) {
  const fs::path dir = fs::path(SHEARBENCH_SOURCE_DIR) / "tests" / "data" / "fuzz" / target;
  std::size_t n = 0;
  if (!fs::is_directory(dir)) return n;
  for (const auto& e : fs::directory_iterator(dir)) {
    std::ifstream in(e.path(), std::ios::binary);
    const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    INFO("input " << e.path().string());
    CHECK_NOTHROW(one(bytes.data(), bytes.size()));
    ++n;
  }
  return n;
}

}  // namespace

TEST_CASE("inputs that crashed the fuzzers are handled", "[fuzz-regress]") {
  // fuzz_mesh found a PLY header whose misspelt "element" line made OpenMesh's reader write through a
  // null element (SEGV), and an "element" line whose count did not parse (read as 0) on which it looped
  // for ever (timeout); the header is now checked against the PLY grammar first.
  // Session 4: PLY list counts OpenMesh hung on (negative, 2^30), and OFF counts on the magic line, which
  // OpenMesh reads from the next line instead ("0-4": a face count of -4, out of memory), and a number
  // left over on an OFF face line (read as the next face's count: out of memory).
  CHECK(replay("fuzz_mesh", sb::fuzz::one_mesh) >=
        13);  // and an OFF magic token with a digit glued on   // binary OFF, whose reader trusts every count, is
              // refused   // and OFF counts: negative, or a face line without one
  CHECK(replay("fuzz_tsd_dataset", sb::fuzz::one_tsd_dataset) >= 1);  // the same number overflow in dataset.json
  replay("fuzz_tsd_csv", sb::fuzz::one_tsd_csv);
  replay("fuzz_scene", sb::fuzz::one_scene);
  // fuzz_params found a number too large for a double: nlohmann throws out_of_range (not parse_error),
  // which escaped the JSON loader; every JSON file is read through jsonin::load_file, which now converts it.
  CHECK(replay("fuzz_params", sb::fuzz::one_params) >= 1);
  CHECK(replay("fuzz_session", sb::fuzz::one_session) >= 1);  // and in a session file
}

}  // namespace test_fuzz_regressions
