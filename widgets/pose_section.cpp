#include "widgets/pose_section.hpp"

#include <imgui.h>

#include <utility>

#include "widgets/panels.hpp"

namespace sb::ui {

void PoseSection::drag_to(const Pose& X_EI, AppState& state, bool skip_same, EditOrigin origin) {
  if (skip_same && last_drag_ && X_EI.isApprox(*last_drag_, 1e-12)) return;
  state.request_drag(X_EI, std::move(origin));
  last_drag_ = X_EI;
}

void PoseSection::nudge(const Pose& delta_E, bool rotate, const AppSnapshot& snap, AppState& state) {
  Pose X = last_drag_ ? *last_drag_ : snap.X_EI;
  if (rotate) X.linear() = delta_E.linear() * X.linear();  // about the indenter origin, axes of E
  X.translation() += delta_E.translation();
  drag_to(X, state, false, {"nudge of the indenter", 0});
}

void PoseSection::draw(const AppSnapshot& snap, bool dragging, AppState& state) {
  Pose X = shown(snap, dragging);
  if (pose_panel(X)) {
    if (panel_gesture_ == 0) panel_gesture_ = state.new_gesture();
    drag_to(X, state, false, {"edit of the indenter pose", panel_gesture_});
  }
  if (!ImGui::IsAnyItemActive()) panel_gesture_ = 0;           // the field let go: the next edit is an entry of its own
  ImGui::TextDisabled("drag it in the 3D view; F1 for keys");  // Undo / Redo follow on this line
}

}  // namespace sb::ui
