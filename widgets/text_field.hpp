#pragma once
// Small ImGui helpers shared by the workbench's sections: text fields backed by std::string (the vendored
// Debian ImGui ships imgui_stdlib.h without compiling it, so the same resize callback lives here), and the
// one width the control column gives a field with a label or buttons to its right.
#include <imgui.h>

#include <string>

namespace sb::ui {

// ImGui::InputText / InputTextWithHint on a std::string that grows as the user types.
bool input_text(const char* label, std::string& text, ImGuiInputTextFlags flags = 0);
bool input_text_with_hint(const char* label, const char* hint, std::string& text, ImGuiInputTextFlags flags = 0);

// Whether Enter was pressed in the text field just drawn: call it right after the field (drawn with
// ImGuiInputTextFlags_EnterReturnsTrue) with what the field returned. ImGui 1.86 reads a key as down or up at
// a frame's start, so an Enter pressed and released within one event poll (a quick tap on a slow frame) never
// reaches the field, which stays active and takes the next keys as typing. The window records every press
// (keys.cpp): an active field takes that press and ends its editing as Enter would.
bool entered(bool field_returned);

// The next item leaves 110 px at the right of the control column: room for a label ("colour max",
// "3D markers") or two small buttons (Load / Save, Open / Save, Export fields).
void next_item_leaves_label_room();

}  // namespace sb::ui
