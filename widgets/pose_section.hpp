#pragma once
// The Indenter pose section and every other way the pose is moved by hand (a drag in the 3D view, the
// keyboard's nudges): it owns the pose last asked for, so a drag continues from where it is, not from the
// snapshot that has not caught up yet.
#include <optional>
#include <string>

#include "core/workbench/app_state.hpp"

namespace sb::ui {

class PoseSection {
 public:
  // A new session: no drag in progress.
  void reset() {
    last_drag_.reset();
    refusal_.clear();
    typed_.reset();
  }
  // The pose to show: the one being dragged while `dragging`, else the snapshot's.
  Pose shown(const AppSnapshot& snap, bool dragging) const { return last_drag_ && dragging ? *last_drag_ : snap.X_EI; }
  // Asks the sync point for `X_EI` (unless it is the pose already asked for, when `skip_same`).
  // `origin`: the undo history's name and gesture for it (every mouse move of one drag shares a gesture).
  void drag_to(const Pose& X_EI, AppState& state, bool skip_same = false, EditOrigin origin = {});
  // A keyboard nudge: translation of `delta_E`, its rotation about the indenter origin when `rotate`.
  void nudge(const Pose& delta_E, bool rotate, const AppSnapshot& snap, AppState& state);
  void draw(const AppSnapshot& snap, bool dragging, AppState& state);

 private:
  void ask_checked(const Pose& X_EI, AppState& state);

  std::optional<Pose> last_drag_;
  std::optional<Pose> typed_;        // typed into a field still being edited
  std::string refusal_;              // why the last typed pose was refused, shown under the fields until the next edit
  std::uint64_t panel_gesture_ = 0;  // the pose fields' edit in progress (0: none)
};

}  // namespace sb::ui
