#include "widgets/pose_section.hpp"

#include <imgui.h>

#include <utility>

#include "core/workbench/value_check.hpp"
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

// A typed pose under the gel's back or out of reach is refused where it was typed; the pose stays.
void PoseSection::ask_checked(const Pose& X_EI, AppState& state) {
  const PoseCheck check = check_indenter_pose(X_EI, state.sensor()->gel.thickness_m);
  refusal_ = check.message;
  if (check.accepted) drag_to(X_EI, state, false, {"edit of the indenter pose", panel_gesture_});
}

void PoseSection::draw(const AppSnapshot& snap, bool dragging, AppState& state) {
  Pose X = shown(snap, dragging);
  // A value typed (Ctrl+click) is applied when its field is left: ImGui applies each key's text, and "-2" on the
  // way to "-20" is not the pose asked for.
  if (pose_panel(X)) {
    if (panel_gesture_ == 0) panel_gesture_ = state.new_gesture();
    if (ImGui::GetIO().WantTextInput)
      typed_ = X;
    else
      ask_checked(X, state);
  }
  if (typed_ && !ImGui::IsAnyItemActive()) {
    ask_checked(*typed_, state);
    typed_.reset();
  }
  if (!ImGui::IsAnyItemActive()) panel_gesture_ = 0;  // the field let go: the next edit is an entry of its own
  if (!refusal_.empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.55f, 0.45f, 1.0f));
    ImGui::TextWrapped("%s", refusal_.c_str());
    ImGui::PopStyleColor();
  }
  ImGui::TextDisabled("drag it in the 3D view; F1 for keys");  // Undo / Redo follow on this line
}

}  // namespace sb::ui
