#pragma once
// The undo/redo history of the user's edits to the simulation state: the indenter's path (a drag, a nudge, a
// pose typed in, a path replaced) and a model's parameter table (a slider, a loaded or fitted table). AppState
// records every edit it applies here (core/workbench/app_state.hpp), so every source of edits is covered in
// one place, and applies an undo or a redo through its queue like any other edit.
//
// An entry holds the state before and after its edit; an undo hands back the entry whose `before` is to be
// restored, a redo the one whose `after` is. One gesture is one entry: an edit that carries the gesture id
// of the newest entry (a drag's mouse moves, a slider's frames) extends it (its `before` stays). Bounded: the
// oldest entries go first, past `capacity` entries or `max_stored_poses` poses kept in all paths together.
#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "core/base/params.hpp"
#include "core/geometry/pose.hpp"

namespace sb {

// What a path edit changes: the path, the step shown, and how many of its first steps are still the measured
// (dataset) path. Shared: an entry's `after` is usually the next entry's `before`.
struct PathEditState {
  std::shared_ptr<const std::vector<Pose>> path;
  int step = -1;
  int measured_steps = 0;
};

// What a parameter edit changes: one model slot's whole table.
struct ParamsEditState {
  std::size_t model = 0;
  ParamSet params;
};

using EditState = std::variant<PathEditState, ParamsEditState>;

struct EditEntry {
  std::string label;  // what the Undo button's tooltip names: "drag of the indenter"
  EditState before, after;
  std::uint64_t gesture = 0;  // 0: an edit of its own (never extended)
};

class EditHistory {
 public:
  static constexpr std::size_t kDefaultCapacity = 200;
  // 200 entries of two 1000-step paths; a pose is 128 bytes, so ~50 MB at most.
  static constexpr std::size_t kDefaultMaxStoredPoses = 400'000;

  // @pre capacity >= 1
  explicit EditHistory(std::size_t capacity = kDefaultCapacity, std::size_t max_stored_poses = kDefaultMaxStoredPoses);

  // An edit was applied. It extends the newest entry when both carry the same non-zero gesture and change the
  // same thing (the path, or the same model's table); else it is a new entry. Either way the redo side is
  // cleared: a new edit after an undo starts a new branch.
  void record(EditEntry entry);
  // The newest entry (moved to the redo side): restore its `before`. None when there is nothing to undo.
  std::optional<EditEntry> undo();
  // The entry undone last (moved back to the undo side): restore its `after`. None when nothing was undone.
  std::optional<EditEntry> redo();
  // A model slot got another model: its tables do not apply to it, so their entries go (both sides).
  void forget_model(std::size_t model);
  void clear();

  std::size_t undo_size() const { return undo_.size(); }
  std::size_t redo_size() const { return redo_.size(); }
  // The label of what undo() / redo() would take back ("" when nothing).
  std::string undo_label() const { return undo_.empty() ? std::string() : undo_.back().label; }
  std::string redo_label() const { return redo_.empty() ? std::string() : redo_.back().label; }

 private:
  bool extends_newest(const EditEntry& entry) const;
  void trim();
  std::size_t stored_poses() const;

  std::size_t capacity_, max_stored_poses_;
  std::deque<EditEntry> undo_;   // oldest first
  std::vector<EditEntry> redo_;  // the next redo last
};

}  // namespace sb
