// core/unsaved_work: when the workbench's session is dirty and when an autosave is due.
#include <catch2/catch.hpp>

#include <cstdlib>

#include "core/workbench/unsaved_work.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_unsaved_work {

TEST_CASE("dirty follows the document, not the edits", "[session][autosave]") {
  sb::UnsavedWork w(30.0);
  w.saved("A");
  w.observe("A", 0.0);
  CHECK_FALSE(w.dirty());
  w.observe("B", 1.0);
  CHECK(w.dirty());
  w.observe("A", 2.0);  // dragged back to where it was saved: nothing to lose
  CHECK_FALSE(w.dirty());
}

TEST_CASE("an autosave is due interval seconds after the first unsaved change", "[session][autosave]") {
  // Change at t = 1 s, interval 30 s: due from t = 31 s on, not before; a continuing drag (C at 20 s)
  // does not push the deadline back, or a long drag would never be autosaved.
  sb::UnsavedWork w(30.0);
  w.saved("A");
  w.observe("B", 1.0);
  CHECK_FALSE(w.autosave_due(30.9));
  w.observe("C", 20.0);
  CHECK(w.autosave_due(31.0));
  w.autosaved();
  CHECK(w.dirty());  // autosaved is not saved: closing still asks
  CHECK_FALSE(w.autosave_due(100.0));
  w.observe("D", 40.0);  // a new change restarts the clock
  CHECK_FALSE(w.autosave_due(69.9));
  CHECK(w.autosave_due(70.0));
}

TEST_CASE("a restored autosave is dirty but not due", "[session][autosave]") {
  sb::UnsavedWork w(30.0);
  w.restored("R");
  w.observe("R", 0.0);
  CHECK(w.dirty());
  CHECK_FALSE(w.autosave_due(1000.0));
  w.saved("R");
  CHECK_FALSE(w.dirty());
}

TEST_CASE("the autosave path follows SHEARBENCH_AUTOSAVE, then XDG_STATE_HOME", "[session][autosave]") {
  ::setenv("SHEARBENCH_AUTOSAVE", "/tmp/x/auto.json", 1);
  CHECK(sb::default_autosave_path() == "/tmp/x/auto.json");
  ::unsetenv("SHEARBENCH_AUTOSAVE");
  const char* old = std::getenv("XDG_STATE_HOME");
  const std::string saved = old ? old : "";
  ::setenv("XDG_STATE_HOME", "/state", 1);
  CHECK(sb::default_autosave_path() == "/state/shearbench/autosave.json");
  if (old)
    ::setenv("XDG_STATE_HOME", saved.c_str(), 1);
  else
    ::unsetenv("XDG_STATE_HOME");
}

TEST_CASE("the default session path is in the user's state folder, not the working folder", "[session]") {
  const char* old = std::getenv("XDG_STATE_HOME");
  const std::string saved = old ? old : "";
  ::setenv("XDG_STATE_HOME", "/state", 1);
  CHECK(sb::default_session_path() == "/state/shearbench/session.json");
  ::unsetenv("XDG_STATE_HOME");
  const char* home = std::getenv("HOME");
  if (home && *home) CHECK(sb::default_session_path() == std::string(home) + "/.local/state/shearbench/session.json");
  if (old) ::setenv("XDG_STATE_HOME", saved.c_str(), 1);
}

}  // namespace test_unsaved_work
