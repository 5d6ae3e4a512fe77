// core/workbench/open_target: what the workbench's Open field opens.
#include <catch2/catch.hpp>

#include "temp_path.hpp"

#include <filesystem>
#include <fstream>

#include "core/base/error.hpp"
#include "core/workbench/open_target.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_open_target {

namespace fs = std::filesystem;

namespace {
void write(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}
}  // namespace

TEST_CASE("Open tells a dataset, a scene and a session apart, resolving paths as the command line does", "[open]") {
  const fs::path root = sbtest::temp_path("sb_test_open_root");
  const fs::path work = sbtest::temp_path("sb_test_open_work");
  write(root / "twin" / "twin_a" / "dataset.json", "{}");
  write(work / "scenes" / "press.json", R"({"name": "press"})");
  write(work / "mine.json", R"({"format": "shearbench-session", "version": 2, "open": {}})");
  write(work / "notes.txt", "x");
  const std::string r = root.string(), w = work.string();
  using sb::OpenKind;
  // A dataset by data:, by a path relative to the data root (not in the working folder), and by its dataset.json.
  CHECK(sb::classify_open_target("data:twin/twin_a", r, w).kind == OpenKind::kDataset);
  const sb::OpenTarget rel = sb::classify_open_target("twin/twin_a", r, w);
  CHECK(rel.kind == OpenKind::kDataset);
  CHECK(rel.path == (root / "twin/twin_a").string());
  CHECK(sb::classify_open_target("twin/twin_a/dataset.json", r, w).path == (root / "twin/twin_a").string());
  // A scene is a scene, not a session (Session -> Open on a scene adopted its path).
  CHECK(sb::classify_open_target("scenes/press.json", r, w).kind == OpenKind::kScene);
  CHECK(sb::classify_open_target("mine.json", r, w).kind == OpenKind::kSession);
  // Errors name the file.
  CHECK_THROWS_WITH(sb::classify_open_target("nowhere", r, w), Catch::Contains((work / "nowhere").string()));
  CHECK_THROWS_AS(sb::classify_open_target("notes.txt", r, w), sb::InputError);
  CHECK_THROWS_WITH(sb::classify_open_target("twin", r, w), Catch::Contains("without dataset.json"));
  // The list offers the scenes and the datasets.
  const auto list = sb::open_suggestions(r, (work / "scenes").string());
  REQUIRE(list.size() == 2);
  CHECK(list[0] == (work / "scenes" / "press.json").string());
  CHECK(list[1] == "data:twin/twin_a");
  fs::remove_all(root);
  fs::remove_all(work);
}

TEST_CASE("the recent list keeps the newest first, once each", "[open]") {
  sb::RecentPaths recent(3);
  for (const char* p : {"a", "b", "a", "c", "d"}) recent.add(p);
  CHECK(recent.paths() == std::vector<std::string>{"d", "c", "a"});
}

}  // namespace test_open_target
