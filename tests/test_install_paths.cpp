// Where shearbench finds its own files (core/base/install_paths.hpp): every expected path below is laid
// out and derived by hand, so the test says what the lookup must give, not what it happens to give.
#include <catch2/catch.hpp>

#include "temp_path.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "core/base/data_root.hpp"
#include "core/base/error.hpp"
#include "core/base/install_paths.hpp"
#include "core/data/scene.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_install_paths {

namespace fs = std::filesystem;

namespace {

void touch(const fs::path& p, const std::string& text = "") {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

}  // namespace

TEST_CASE("an installed executable finds <prefix>/share/shearbench", "[install_paths]") {
  const fs::path prefix = sbtest::temp_path("sb_test_install_prefix");
  fs::remove_all(prefix);
  touch(prefix / "bin" / "shearbench");
  fs::create_directories(prefix / "share" / "shearbench" / "assets" / "params");
  const std::string exe = (prefix / "bin" / "shearbench").string();
  CHECK(sb::find_home(exe, "", "") == (prefix / "share" / "shearbench").string());
  // Through a symlink elsewhere (/usr/local/bin/shearbench -> <prefix>/bin/shearbench): the real file's prefix.
  touch(prefix / "elsewhere" / "placeholder");
  fs::create_symlink(prefix / "bin" / "shearbench", prefix / "elsewhere" / "shearbench");
  CHECK(sb::find_home((prefix / "elsewhere" / "shearbench").string(), "", "") ==
        (prefix / "share" / "shearbench").string());
  // An installed home is not a source checkout: no ../shared/data default beside it.
  CHECK_FALSE(sb::is_source_checkout((prefix / "share" / "shearbench").string()));
  fs::remove_all(prefix);
}

TEST_CASE("a build folder's executable finds the source tree named in shearbench-home", "[install_paths]") {
  const fs::path root = sbtest::temp_path("sb_test_install_build");
  fs::remove_all(root);
  const fs::path source = root / "checkout", build = root / "checkout" / "build";
  fs::create_directories(source / "assets" / "params");
  fs::create_directories(source / "core");
  touch(source / "CMakeLists.txt");
  touch(build / "shearbench");
  touch(build / "shearbench-home", source.string() + "\n");
  CHECK(sb::find_home((build / "shearbench").string(), "", "") == source.string());
  CHECK(sb::is_source_checkout(source.string()));
  // The checkout renamed: the file names a folder that is gone, and nothing else is found.
  fs::rename(source, root / "moved");
  CHECK(sb::find_home((root / "moved" / "build" / "shearbench").string(), "", "").empty());
  fs::remove_all(root);
}

TEST_CASE("--home, then SHEARBENCH_HOME, override where the executable is", "[install_paths]") {
  const fs::path root = sbtest::temp_path("sb_test_install_override");
  fs::remove_all(root);
  fs::create_directories(root / "share" / "shearbench" / "assets" / "params");
  touch(root / "bin" / "shearbench");
  const std::string exe = (root / "bin" / "shearbench").string();
  CHECK(sb::find_home(exe, (root / "flag").string(), (root / "env").string()) == (root / "flag").string());
  CHECK(sb::find_home(exe, "", (root / "env").string()) == (root / "env").string());
  // A relative override is made absolute against the working folder.
  CHECK(sb::find_home(exe, "", "rel/home") == (fs::current_path() / "rel" / "home").string());
  // No executable path and no override: nothing.
  CHECK(sb::find_home("", "", "").empty());
  fs::remove_all(root);
}

TEST_CASE("a shared library finds its home from where it is, not from the program that loaded it", "[install_paths]") {
  if (const char* env = std::getenv("SHEARBENCH_HOME"); env && *env) {
    WARN("SHEARBENCH_HOME is set: it overrides the library's lookup");
    return;
  }
  const fs::path prefix = sbtest::temp_path("sb_test_install_library");
  fs::remove_all(prefix);
  fs::create_directories(prefix / "share" / "shearbench" / "assets" / "params");
  // <prefix>/lib/libshearbench.so.0 is its own anchor; under lib/<multiarch>/ the anchor is one level up.
  const std::string plain = (prefix / "lib" / "libshearbench.so.0").string();
  CHECK(sb::library_home_anchor(plain) == plain);
  CHECK(sb::library_home_anchor((prefix / "lib" / "x86_64-linux-gnu" / "libshearbench.so.0").string()) == plain);
  CHECK(sb::library_home_anchor("/build/libshearbench.so") == "/build/libshearbench.so");
  sb::set_home_anchor(plain);
  CHECK(sb::home_dir() == (prefix / "share" / "shearbench").string());
  sb::set_home_anchor("");  // back to the test binary's own home
  CHECK(sb::home_dir() != (prefix / "share" / "shearbench").string());
  fs::remove_all(prefix);
}

TEST_CASE("home_dir rejects an override without assets/params, naming both ways to set it", "[install_paths]") {
  const fs::path empty = sbtest::temp_path("sb_test_install_empty_home");
  fs::create_directories(empty);
  sb::set_home_flag(empty.string());
  try {
    sb::home_dir();
    FAIL("home_dir accepted a folder without assets/params");
  } catch (const sb::InputError& e) {
    CHECK(e.file() == empty.string());
    CHECK_THAT(e.what(),
               Catch::Contains("SHEARBENCH_HOME") && Catch::Contains("--home") && Catch::Contains("assets/params"));
  }
  sb::set_home_flag("");
  fs::remove_all(empty);
}

TEST_CASE("the test binary's home is this source tree (build/shearbench-home)", "[install_paths]") {
  if (const char* env = std::getenv("SHEARBENCH_HOME"); env && *env) {
    WARN("SHEARBENCH_HOME is set: the build folder's own lookup is not what home_dir sees");
    return;
  }
  CHECK(fs::equivalent(sb::home_dir(), SHEARBENCH_SOURCE_DIR));
}

TEST_CASE("a data: path with no data root names --data and SHEARBENCH_DATA", "[install_paths][data_root]") {
  try {
    sb::resolve_path("data:twin/twin_sphere8", "", "");
    FAIL("resolve_path accepted a data: path without a root");
  } catch (const sb::InputError& e) {
    CHECK(e.file() == "data:twin/twin_sphere8");
    CHECK_THAT(e.what(), Catch::Contains("--data") && Catch::Contains("SHEARBENCH_DATA"));
  }
  // Paths that are not data: need no root.
  CHECK(sb::resolve_path("/abs/set", "", "") == "/abs/set");
}

TEST_CASE("a scene naming data: with no data root says which file and entry asked for it", "[install_paths][scene]") {
  const nlohmann::json j = nlohmann::json::parse(R"({
    "sensor": {"gel": "flat", "markers": "7x9"},
    "indenter": {"shape": "mesh", "mesh": "data:meshes/cow.obj", "scale": 0.002},
    "trajectory": {"dt_s": 0.1, "keyframes": [{"t_s": 0, "xyz_m": [0, 0, 0.005]}, {"t_s": 0.2, "xyz_m": [0, 0, 0.004]}]}})");
  try {
    sb::parse_scene(j, "scenes/press_cow.json", "", "");
    FAIL("parse_scene accepted a data: mesh without a data root");
  } catch (const sb::InputError& e) {
    CHECK(e.file() == "scenes/press_cow.json");
    CHECK_THAT(e.what(), Catch::Contains("/indenter/mesh") && Catch::Contains("data:meshes/cow.obj") &&
                             Catch::Contains("--data") && Catch::Contains("SHEARBENCH_DATA"));
  }
}

}  // namespace test_install_paths
