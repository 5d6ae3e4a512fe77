#include "core/workbench/work_keeper.hpp"

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "temp_path.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_work_keeper {

using sb::SessionFile;
using sb::WorkBaseline;
using sb::WorkKeeper;
namespace fs = std::filesystem;

// A session the test edits, and the physics' queue of edits not yet applied.
struct FakeSession {
  SessionFile file;
  std::size_t pending = 0;
  WorkKeeper::Source source() {
    return {[this] { return pending; }, [this] { return file; }};
  }
};

// An edit the user would be asked about: a model parameter (the step shown is not one).
void edit(FakeSession& s, double value) { s.file.params["hydroshear"]["mu"] = value; }

constexpr double kAutosaveS = 30.0;

TEST_CASE("the work is clean once the opened session's edits are applied, dirty after an edit", "[work_keeper]") {
  const fs::path dir = sbtest::temp_path("work_keeper_clean");
  fs::create_directories(dir);
  FakeSession s;
  WorkKeeper keeper(kAutosaveS, (dir / "autosave.json").string(), s.source());
  keeper.expect_baseline(WorkBaseline::kClean);
  s.pending = 2;  // the baseline waits for the physics
  edit(s, 0.5);
  REQUIRE(keeper.tick(0.0));
  CHECK_FALSE(keeper.tick(0.2));  // checks twice a second, not every frame
  s.pending = 0;
  const auto check = keeper.tick(0.6);
  REQUIRE(check);
  CHECK_FALSE(check->dirty);  // the edits the session opened with are its baseline
  s.file.step = 40;           // playing a replay is not work to ask about
  CHECK_FALSE(keeper.tick(1.2)->dirty);
  edit(s, 0.7);
  CHECK(keeper.tick(1.8)->dirty);
  CHECK(keeper.dirty());
  // An edit between two ticks is seen by dirty_now, not by dirty until the next tick.
  keeper.tick(2.4);
  edit(s, 0.5);  // back to the baseline's value: clean
  CHECK(keeper.dirty());
  CHECK_FALSE(keeper.dirty_now(2.5));
  CHECK_FALSE(keeper.saved_once());
  fs::remove_all(dir);
}

TEST_CASE("dirty work is autosaved after the interval, and a save makes the autosave stale", "[work_keeper]") {
  const fs::path dir = sbtest::temp_path("work_keeper_autosave");
  fs::create_directories(dir);
  FakeSession s;
  WorkKeeper keeper(kAutosaveS, (dir / "autosave.json").string(), s.source());
  keeper.tick(0.0);  // the clean baseline
  edit(s, 0.9);
  keeper.tick(1.0);  // dirty from t = 1 s
  CHECK_FALSE(keeper.has_autosave());
  keeper.tick(1.0 + kAutosaveS - 1.0);
  CHECK_FALSE(keeper.has_autosave());
  keeper.tick(1.0 + kAutosaveS + 0.5);
  CHECK(keeper.has_autosave());
  CHECK(sb::load_session_file(keeper.autosave_path()).params == s.file.params);

  const std::string saved = (dir / "session.json").string();
  sb::save_session_file(saved, s.file);
  keeper.saved_to(saved);
  CHECK_FALSE(keeper.dirty());
  CHECK(keeper.saved_once());
  CHECK_FALSE(keeper.has_autosave());
  fs::remove_all(dir);
}

TEST_CASE("a failed autosave is reported, not thrown", "[work_keeper]") {
  const fs::path dir = sbtest::temp_path("work_keeper_refused");
  fs::create_directories(dir);
  const fs::path not_a_session = dir / "scene.json";
  { std::ofstream(not_a_session) << "{\"format\": \"something else\"}\n"; }
  FakeSession s;
  WorkKeeper keeper(kAutosaveS, not_a_session.string(), s.source());
  keeper.tick(0.0);
  edit(s, 1.1);
  keeper.tick(1.0);
  const auto check = keeper.tick(2.0 + kAutosaveS);
  REQUIRE(check);
  CHECK(check->dirty);
  CHECK_FALSE(check->autosave_error.empty());
  fs::remove_all(dir);
}

TEST_CASE("a restored autosave is unsaved work; a close asks until the user answers", "[work_keeper]") {
  const fs::path dir = sbtest::temp_path("work_keeper_restored");
  fs::create_directories(dir);
  FakeSession s;
  edit(s, 0.3);
  WorkKeeper keeper(kAutosaveS, (dir / "autosave.json").string(), s.source());
  keeper.expect_baseline(WorkBaseline::kRestored);
  CHECK(keeper.tick(0.0)->dirty);
  CHECK(keeper.unsaved_on_close(0.1));
  keeper.confirm_close();
  CHECK_FALSE(keeper.unsaved_on_close(0.2));
  keeper.discard_autosave();  // nothing there: no error
  CHECK_FALSE(keeper.has_autosave());
  fs::remove_all(dir);
}

}  // namespace test_work_keeper
