// Data-root paths: "data:<relative>" resolves under the root, and data_path is its inverse for display.
#include <catch2/catch.hpp>

#include <filesystem>

#include "core/base/data_root.hpp"

namespace fs = std::filesystem;

TEST_CASE("data_path shows a file under the data root as data:<relative>, others unchanged", "[data_root]") {
  const fs::path root = fs::temp_directory_path() / "sb_test_data_root";
  fs::create_directories(root / "twin" / "set");
  const std::string r = root.string();
  CHECK(sb::data_path((root / "twin" / "set").string(), r) == "data:twin/set");
  // A path that walks out and back in is the same folder.
  CHECK(sb::data_path((root / "twin" / ".." / "twin" / "set").string(), r) == "data:twin/set");
  CHECK(sb::resolve_path("data:twin/set", r, "") == (root / "twin/set").string());
  // Outside the root, the root itself, and already data: paths stay as they are.
  CHECK(sb::data_path("/elsewhere/set", r) == "/elsewhere/set");
  CHECK(sb::data_path(r, r) == r);
  CHECK(sb::data_path((root / ".." / "x").string(), r) == (root / ".." / "x").string());
  CHECK(sb::data_path("data:twin/set", r) == "data:twin/set");
  CHECK(sb::data_path("", r).empty());
  fs::remove_all(root);
}
