#include <catch2/catch.hpp>

#include <filesystem>
#include "temp_path.hpp"

#include "core/base/display_path.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_display_path {

using namespace sb;
namespace fs = std::filesystem;

TEST_CASE("display_path: data: inside the data root, relative inside the working folder, else as given",
          "[display_path]") {
  const fs::path tmp = sbtest::temp_path("sb_display_path_test");
  fs::remove_all(tmp);
  fs::create_directories(tmp / "data/twin/set");
  fs::create_directories(tmp / "repo/tests/out");
  fs::create_directories(tmp / "elsewhere");
  const std::string root = (tmp / "data").string(), repo = (tmp / "repo").string();
  CHECK(display_path((tmp / "data/twin/set").string(), root, repo) == "data:twin/set");
  CHECK(display_path((tmp / "repo/tests/out").string(), root, repo) == "tests/out");
  // Outside both: a relative form would need "..", so the path stays as it was.
  CHECK(display_path((tmp / "elsewhere").string(), root, repo) == (tmp / "elsewhere").string());
  // Relative and data: paths are already machine-independent.
  CHECK(display_path("scenes/default.json", root, repo) == "scenes/default.json");
  CHECK(display_path("data:twin/set", root, repo) == "data:twin/set");
  fs::remove_all(tmp);
}

}  // namespace test_display_path
