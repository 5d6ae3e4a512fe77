// Data-root paths: "data:<relative>" resolves under the root, and data_path is its inverse for display.
#include <catch2/catch.hpp>

#include "temp_path.hpp"

#include <filesystem>

#include "core/base/data_root.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_data_root {

namespace fs = std::filesystem;

TEST_CASE("data_path shows a file under the data root as data:<relative>, others unchanged", "[data_root]") {
  const fs::path root = sbtest::temp_path("sb_test_data_root");
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

TEST_CASE("a relative data root is made absolute once, so a scene's folder cannot move it", "[data_root]") {
  // From a working folder W with a data root "rel/data": the root is W/rel/data; a scene in W/scenes
  // naming data:meshes/m.obj resolves to W/rel/data/meshes/m.obj, not W/scenes/rel/data/meshes/m.obj
  // (joining a relative root to the scene's folder was the bug).
  const fs::path work = sbtest::temp_path("sb_test_data_root_rel");
  fs::create_directories(work / "rel" / "data" / "meshes");
  fs::create_directories(work / "scenes");
  const fs::path saved = fs::current_path();
  fs::current_path(work);
  const std::string root = sb::resolve_data_root("rel/data");
  const std::string mesh = sb::resolve_path("data:meshes/m.obj", root, (work / "scenes").string());
  fs::current_path(saved);
  CHECK(fs::path(root).is_absolute());
  CHECK(fs::path(root) == (work / "rel" / "data").lexically_normal());
  // The resolved mesh path, joined once more to the scene's folder (as the indenter loader does), stays put.
  CHECK(sb::resolve_path(mesh, root, (work / "scenes").string()) ==
        (work / "rel" / "data" / "meshes" / "m.obj").string());
  fs::remove_all(work);
}

TEST_CASE("a typed relative path falls back to the data root when it is not in the working folder", "[data_root]") {
  const fs::path root = sbtest::temp_path("sb_test_user_path_root");
  const fs::path work = sbtest::temp_path("sb_test_user_path_work");
  fs::create_directories(root / "twin" / "twin_sphere35");
  fs::create_directories(work / "here");
  const std::string r = root.string(), w = work.string();
  // "twin/twin_sphere35" is not in the working folder: the data root's.
  CHECK(sb::resolve_user_path("twin/twin_sphere35", r, w) == (root / "twin/twin_sphere35").string());
  // In the working folder: the working folder's, even when the data root has one too.
  fs::create_directories(root / "here");
  CHECK(sb::resolve_user_path("here", r, w) == (work / "here").string());
  // data: and absolute paths as before; nowhere: the working folder's (the error names where the user is).
  CHECK(sb::resolve_user_path("data:twin", r, w) == (root / "twin").string());
  CHECK(sb::resolve_user_path((root / "twin").string(), r, w) == (root / "twin").string());
  CHECK(sb::resolve_user_path("nowhere/x", r, w) == (work / "nowhere/x").string());
  fs::remove_all(root);
  fs::remove_all(work);
}

}  // namespace test_data_root
