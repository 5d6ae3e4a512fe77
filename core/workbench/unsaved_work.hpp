#pragma once
// "Never lose the user's work" bookkeeping for the workbench, without GL so it is unit-tested: the
// session document (session_to_json text) is observed every so often; it is dirty when it differs from
// the last saved one; an autosave is due when it has been dirty and not autosaved for `interval_s`.
#include <cstddef>
#include <optional>
#include <string>

namespace sb {

class UnsavedWork {
 public:
  explicit UnsavedWork(double autosave_interval_s = 30.0) : interval_s_(autosave_interval_s) {}

  // The document as it is now (called each time the UI may have changed it) at time `now_s`.
  void observe(const std::string& document, double now_s);
  // The user saved (or opened) this document: it is the new clean state.
  void saved(const std::string& document);
  // The document observed last was written to the autosave file.
  void autosaved();
  // This document was restored from an autosave: unsaved (dirty), but already autosaved.
  void restored(const std::string& document);

  bool dirty() const { return current_ != clean_; }
  bool autosave_due(double now_s) const;

 private:
  double interval_s_;
  std::size_t clean_ = 0;  // hashes of the documents (0: none yet)
  std::size_t current_ = 0;
  std::size_t autosaved_ = 0;
  std::optional<double> dirty_since_s_;  // when the current unsaved, un-autosaved change began
};

// Where the workbench autosaves: $SHEARBENCH_AUTOSAVE, else $XDG_STATE_HOME/shearbench/autosave.json,
// else ~/.local/state/shearbench/autosave.json (current folder when HOME is unset).
std::string default_autosave_path();
// Where Ctrl+S saves a session that was never saved or opened: $XDG_STATE_HOME/shearbench/session.json,
// else ~/.local/state/shearbench/session.json (never the working folder, which is often a repository).
std::string default_session_path();

}  // namespace sb
