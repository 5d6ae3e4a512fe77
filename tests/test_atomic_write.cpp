// core/atomic_write: the one writer every output goes through.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>

#include "core/base/atomic_write.hpp"
#include "core/base/error.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_atomic_write {

namespace fs = std::filesystem;

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

fs::path fresh_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("sb_atomic_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::size_t entries(const fs::path& dir) {
  return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

}  // namespace

TEST_CASE("write_file_atomic creates, replaces and leaves no temporary", "[atomic_write]") {
  const fs::path dir = fresh_dir("replace");
  const fs::path file = dir / "sub" / "out.json";  // the missing folder is created
  sb::write_file_atomic(file.string(), "first");
  CHECK(slurp(file) == "first");
  const std::string binary("a\0b\xff", 4);  // bytes are written as given, NULs included
  sb::write_file_atomic(file.string(), binary);
  CHECK(slurp(file) == binary);
  CHECK(entries(file.parent_path()) == 1);  // only out.json: the temporary was renamed
  fs::remove_all(dir);
}

TEST_CASE("write_file_atomic failures name the path and keep the old file", "[atomic_write]") {
  const fs::path dir = fresh_dir("fail");
  const fs::path blocker = dir / "not_a_folder";
  sb::write_file_atomic(blocker.string(), "old");
  // A regular file where a parent folder should be: the folder cannot be created.
  try {
    sb::write_file_atomic((blocker / "x.json").string(), "new");
    FAIL("expected an InputError");
  } catch (const sb::InputError& e) {
    CHECK(e.file() == (blocker / "x.json").string());
  }
  // The target is a folder: refused, and the folder is not touched.
  fs::create_directories(dir / "folder");
  CHECK_THROWS_AS(sb::write_file_atomic((dir / "folder").string(), "x"), sb::InputError);
  CHECK(fs::is_directory(dir / "folder"));
  CHECK(slurp(blocker) == "old");
  CHECK(entries(dir) == 2);  // no temporaries left behind by the failures
  fs::remove_all(dir);
}

TEST_CASE("the temporary is hidden and in the target's folder", "[atomic_write]") {
  // Same folder: rename(2) is atomic only within one file system. Hidden: readers that list a folder
  // (the tsd reader, the frames tracker) never take it for data.
  const fs::path tmp = sb::atomic_temporary_path("/some/dir/markers.csv");
  CHECK(tmp.parent_path() == fs::path("/some/dir"));
  CHECK(tmp.filename().string().rfind(".markers.csv.tmp.", 0) == 0);
}

TEST_CASE("write_png_atomic writes a PNG that decodes to the same pixels", "[atomic_write]") {
  const fs::path dir = fresh_dir("png");
  const unsigned char grey[6] = {0, 50, 100, 150, 200, 255};  // 2 rows x 3 cols
  sb::write_png_atomic((dir / "g.png").string(), 2, 3, 1, grey);
  const std::string bytes = slurp(dir / "g.png");
  REQUIRE(bytes.size() > 8);
  CHECK(bytes.substr(1, 3) == "PNG");  // the PNG signature
  CHECK_THROWS_AS(sb::write_png_atomic((dir / "bad.png").string(), 2, 3, 2, grey), sb::InputError);
  fs::remove_all(dir);
}

}  // namespace test_atomic_write
