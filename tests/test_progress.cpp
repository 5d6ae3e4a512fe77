// core/progress: cooperative cancellation of long operations.
#include <catch2/catch.hpp>

#include <atomic>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "core/base/progress.hpp"
#include "core/tracking/tracker.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_progress {

TEST_CASE("Progress::check throws Cancelled only once the flag is set", "[progress]") {
  std::atomic<bool> flag{false};
  sb::Progress p;
  CHECK_NOTHROW(p.check("no flag at all"));
  p.cancel = &flag;
  CHECK_NOTHROW(p.check("not yet"));
  flag = true;
  CHECK_THROWS_AS(p.check("now"), sb::Cancelled);
}

TEST_CASE("a cancelled tracking run throws before reading a frame", "[progress][tracker]") {
  // The flag is already set, so the first poll (before the first frame) must throw Cancelled rather
  // than InputError for the frames folder's content: cancellation wins over work.
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("sb_progress_frames_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "000000.png") << "not a png";
  std::atomic<bool> flag{true};
  sb::Progress p;
  p.cancel = &flag;
  CHECK_THROWS_AS(sb::track_frames_dir(dir.string(), sb::TrackerOptions{}, p), sb::Cancelled);
  fs::remove_all(dir);
}

}  // namespace test_progress
