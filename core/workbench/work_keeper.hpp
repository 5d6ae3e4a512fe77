#pragma once
// The interactive GUI's "no lost work": whether the session differs from what was last saved or opened
// (core/workbench/unsaved_work.hpp), its autosave while it does, and what a close must ask first.
#include <cstddef>
#include <functional>
#include <optional>
#include <string>

#include "core/workbench/session_file.hpp"
#include "core/workbench/unsaved_work.hpp"

namespace sb {

// How the clean/unsaved baseline follows a new session: a session file opened is clean, an autosave
// restored is unsaved, anything else the user opened (dataset, scene, sample, parameter set) is a change.
enum class WorkBaseline { kNone, kClean, kRestored };

// What counts as the user's work in a session document: everything but the step shown (playing a replay
// changes it, and that is not an edit worth asking about), the camera and derived display scales.
std::string work_fingerprint(const SessionFile& file);

class WorkKeeper {
 public:
  // What the keeper reads from the running session; `document` is called at most twice a second while idle.
  struct Source {
    std::function<std::size_t()> pending_edits;  // queued edits the physics has not applied yet
    std::function<SessionFile()> document;       // the session file as a save would write it now
  };
  // What a check found (tick).
  struct Check {
    bool dirty = false;
    std::string autosave_error;  // empty: no autosave failed
  };

  WorkKeeper(double autosave_interval_s, std::string autosave_path, Source source);
  const std::string& autosave_path() const { return autosave_path_; }

  // A new session is in place: its baseline is taken once the physics applied the session's edits.
  void expect_baseline(WorkBaseline baseline) { baseline_pending_ = baseline; }
  // Every frame; every 0.5 s it takes a pending baseline, observes the work and autosaves when due.
  std::optional<Check> tick(double now_s);
  // The session was saved to `path`: the work is clean, and the autosave stale (unless it is `path`).
  void saved_to(const std::string& path);
  // A session file was opened (the title says "saved" from now on).
  void opened_session_file() { saved_once_ = true; }
  bool dirty() const { return work_.dirty(); }
  // Whether the work is unsaved at now_s, observed now rather than at the last tick (an edit made a moment
  // before an open or a close counts).
  bool dirty_now(double now_s);
  bool saved_once() const { return saved_once_; }

  bool has_autosave() const;
  void discard_autosave();
  // Asked to close at now_s: whether there is unsaved work the user has not agreed to lose yet.
  bool unsaved_on_close(double now_s);
  // The user answered the close question (saved or discarded).
  void confirm_close() { close_confirmed_ = true; }

 private:
  std::string fingerprint() const { return work_fingerprint(source_.document()); }
  UnsavedWork work_;
  std::string autosave_path_;
  Source source_;
  WorkBaseline baseline_pending_ = WorkBaseline::kClean;
  bool saved_once_ = false;  // saved or opened from a session file at least once
  bool close_confirmed_ = false;
  double last_check_s_ = -1e9;
};

}  // namespace sb
