// core/workbench/output_folder: the files the workbench writes never land in a checkout's working folder.
#include <catch2/catch.hpp>

#include "temp_path.hpp"

#include <filesystem>

#include "core/workbench/output_folder.hpp"

// This file's names in a namespace of its own: the unity build compiles several test files as one unit.
namespace test_output_folder {

namespace fs = std::filesystem;

TEST_CASE("Files go to the chosen folder, else beside the session, else the user's folder", "[output_folder]") {
  const auto never = [](const std::string&) { return false; };
  const auto always = [](const std::string&) { return true; };
  // Beside the session file.
  CHECK(sb::output_folder("", "/home/u/work/s.json", "/home/u/.local/share/shearbench/output", never) ==
        "/home/u/work");
  // A session inside a checkout: the user's folder, not the repository.
  CHECK(sb::output_folder("", "/src/shearbench/s.json", "/u/out", always) == "/u/out");
  // No session path, or a relative one (the working folder): the user's folder.
  CHECK(sb::output_folder("", "", "/u/out", never) == "/u/out");
  CHECK(sb::output_folder("", "s.json", "/u/out", never) == "/u/out");
  // Chosen: absolute as is; relative beside the session, never in the working folder.
  CHECK(sb::output_folder("/tmp/shots", "/home/u/s.json", "/u/out", always) == "/tmp/shots");
  CHECK(sb::output_folder("shots", "/home/u/s.json", "/u/out", never) == "/home/u/shots");
  CHECK(sb::output_folder("shots", "", "/u/out", never) == "/u/out/shots");
  // Paths written inside it.
  CHECK(sb::output_path("fields_export", "/u/out") == "/u/out/fields_export");
  CHECK(sb::output_path("/abs/x", "/u/out") == "/abs/x");
}

TEST_CASE("A checkout is a folder with .git at or above it", "[output_folder]") {
  const fs::path repo = sbtest::temp_path("sb_test_output_folder_repo");
  fs::create_directories(repo / ".git");
  fs::create_directories(repo / "a" / "b");
  const fs::path outside = sbtest::temp_path("sb_test_output_folder_plain");
  fs::create_directories(outside);
  CHECK(sb::inside_git_checkout(repo.string()));
  CHECK(sb::inside_git_checkout((repo / "a" / "b").string()));
  CHECK_FALSE(sb::inside_git_checkout(outside.string()));
  fs::remove_all(repo);
  fs::remove_all(outside);
}

TEST_CASE("The user's folder follows XDG_DATA_HOME", "[output_folder]") {
  const char* old = std::getenv("XDG_DATA_HOME");
  const std::string saved = old ? old : "";
  setenv("XDG_DATA_HOME", "/x/data", 1);
  CHECK(sb::default_user_output_folder() == "/x/data/shearbench/output");
  if (old)
    setenv("XDG_DATA_HOME", saved.c_str(), 1);
  else
    unsetenv("XDG_DATA_HOME");
}

}  // namespace test_output_folder
