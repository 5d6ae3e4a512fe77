#pragma once
// The Session section: the session file's path (Save writes it, Open reads it; a scene or dataset typed here
// opens as in Replay without becoming the session file) and whether the work is saved.
#include <string>

#include "widgets/workbench_request.hpp"

namespace sb::ui {

class SessionSection {
 public:
  // The session file: what the quit dialog saves to. Adopted only once a save or an open succeeded; the
  // field shows it again after a failed open (revert).
  // An adopted path also ends the field's editing: ImGui's Esc would otherwise put back the text the field had
  // when the editing began (the old file) while the quit dialog and the next Ctrl+S write to the adopted one.
  void set_file(const std::string& path) {
    file_ = path;
    field_ = path;
    end_edit_ = true;
  }
  void revert() {
    field_ = file_;
    end_edit_ = true;
  }
  const std::string& file() const { return file_; }
  // What the field says now (Ctrl+S saves there).
  const std::string& field() const { return field_; }
  // "unsaved changes"; a session never saved does not say "saved".
  void set_unsaved(bool unsaved) { unsaved_ = unsaved; }
  void set_saved_once(bool saved) { saved_once_ = saved; }
  // Where screenshots and field exports go (the field's tooltip says it).
  void set_output_folder(const std::string& folder) { output_folder_ = folder; }
  void draw(WorkbenchRequest& req);

 private:
  std::string field_;  // the Session field (what Save writes to)
  std::string file_;   // the adopted session file
  bool unsaved_ = false;
  bool saved_once_ = false;
  bool end_edit_ = false;  // the field's text was set from outside: stop editing it at the next draw
  std::string output_folder_;
};

}  // namespace sb::ui
