#include "widgets/session_section.hpp"

#include <imgui.h>
#include <imgui_internal.h>  // GetActiveID, ClearActiveID: an adopted path ends the editing

#include "widgets/text_field.hpp"

namespace sb::ui {

void SessionSection::draw(WorkbenchRequest& req) {
  if (end_edit_ && ImGui::GetActiveID() == ImGui::GetID("##session")) ImGui::ClearActiveID();
  end_edit_ = false;
  next_item_leaves_label_room();
  // A click selects the whole path, so what is typed replaces it (a path typed into the middle of the old one
  // named a file nobody meant).
  input_text("##session", field_, ImGuiInputTextFlags_AutoSelectAll);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("session file (JSON): %s\nscreenshots (P) and field exports go to: %s", field_.c_str(),
                      output_folder_.c_str());
  ImGui::SameLine();
  if (ImGui::SmallButton("Open##session")) req.open_session = field_;
  ImGui::SameLine();
  if (ImGui::SmallButton("Save##session")) req.save_session = field_;
  if (unsaved_) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.75f, 0.3f, 1.0f));
    ImGui::TextWrapped("unsaved changes (autosaved every 30 s; Ctrl+S saves)");
    ImGui::PopStyleColor();
  } else if (!saved_once_) {
    ImGui::PushTextWrapPos(0.0f);
    ImGui::TextDisabled("new session, not saved yet (Ctrl+S saves it)");
    ImGui::PopTextWrapPos();
  } else {
    ImGui::TextDisabled("saved");
  }
}

}  // namespace sb::ui
