#include "widgets/text_field.hpp"

#include <imgui_internal.h>  // ClearActiveID: ends a field's editing as Enter does

#include "widgets/keys.hpp"

namespace sb::ui {

namespace {
// ImGui asks for a larger buffer as the text grows: the string is resized and its storage handed back.
int resize_string(ImGuiInputTextCallbackData* data) {
  if (data->EventFlag == ImGuiInputTextFlags_CallbackResize) {
    auto* text = static_cast<std::string*>(data->UserData);
    text->resize(static_cast<std::size_t>(data->BufTextLen));
    data->Buf = text->data();
  }
  return 0;
}
}  // namespace

bool input_text(const char* label, std::string& text, ImGuiInputTextFlags flags) {
  return ImGui::InputText(label, text.data(), text.capacity() + 1, flags | ImGuiInputTextFlags_CallbackResize,
                          resize_string, &text);
}

bool input_text_with_hint(const char* label, const char* hint, std::string& text, ImGuiInputTextFlags flags) {
  return ImGui::InputTextWithHint(label, hint, text.data(), text.capacity() + 1,
                                  flags | ImGuiInputTextFlags_CallbackResize, resize_string, &text);
}

bool entered(bool field_returned) {
  if (field_returned) {
    take_enter_press();  // ImGui saw it: nothing else acts on the same press
    return true;
  }
  if (!ImGui::IsItemActive() || !take_enter_press()) return false;
  ImGui::ClearActiveID();
  return true;
}

void next_item_leaves_label_room() { ImGui::SetNextItemWidth(-110); }

}  // namespace sb::ui
