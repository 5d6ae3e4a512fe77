#include "widgets/keys.hpp"

#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <iterator>

#include "core/workbench/double_click.hpp"
#include "core/workbench/held_modifiers.hpp"

namespace sb::ui {

const std::vector<KeyBinding>& key_table() {
  static const std::vector<KeyBinding> table = {
      {GLFW_KEY_SPACE, false, Action::kPlayPause, "Space", "play / pause the replay"},
      {GLFW_KEY_PERIOD, false, Action::kStepForward, ".", "one step forward"},
      {GLFW_KEY_COMMA, false, Action::kStepBack, ",", "one step back"},
      {GLFW_KEY_HOME, false, Action::kRewind, "Home", "back to the start"},
      {GLFW_KEY_END, false, Action::kEnd, "End", "to the last step"},
      {GLFW_KEY_RIGHT, false, Action::kNudgeXPlus, "Right", "nudge the indenter +x (0.1 mm)"},
      {GLFW_KEY_LEFT, false, Action::kNudgeXMinus, "Left", "nudge the indenter -x"},
      {GLFW_KEY_UP, false, Action::kNudgeYPlus, "Up", "nudge the indenter +y"},
      {GLFW_KEY_DOWN, false, Action::kNudgeYMinus, "Down", "nudge the indenter -y"},
      {GLFW_KEY_PAGE_DOWN, false, Action::kPushIn, "PgDn", "push the indenter in (0.05 mm)"},
      {GLFW_KEY_PAGE_UP, false, Action::kPullOut, "PgUp", "pull the indenter out"},
      {GLFW_KEY_E, false, Action::kTwistPlus, "E", "twist +2 deg about the pad normal"},
      {GLFW_KEY_Q, false, Action::kTwistMinus, "Q", "twist -2 deg"},
      {GLFW_KEY_R, false, Action::kCameraReset, "R", "reset the camera"},
      {GLFW_KEY_1, false, Action::kCameraTop, "1", "camera: top"},
      {GLFW_KEY_2, false, Action::kCameraSide, "2", "camera: side"},
      {GLFW_KEY_3, false, Action::kCameraIso, "3", "camera: iso"},
      {GLFW_KEY_EQUAL, false, Action::kArrowsLonger, "+", "longer arrows (all panels)"},
      {GLFW_KEY_MINUS, false, Action::kArrowsShorter, "-", "shorter arrows"},
      {GLFW_KEY_M, false, Action::kNextMarkerModel, "M", "which model moves the 3D markers"},
      {GLFW_KEY_P, false, Action::kScreenshot, "P", "screenshot (PNG)"},
      {GLFW_KEY_F1, false, Action::kToggleHelp, "F1 / H", "this help"},
      {GLFW_KEY_H, false, Action::kToggleHelp, "", ""},
      {GLFW_KEY_S, false, Action::kSaveSession, "Ctrl+S", "save the session (JSON; autosaved every 30 s)", true},
      {GLFW_KEY_Z, false, Action::kUndo, "Ctrl+Z", "undo the last drag, nudge, parameter edit or path replaced", true},
      {GLFW_KEY_Z, true, Action::kRedo, "Ctrl+Shift+Z / Ctrl+Y", "redo what was undone", true},
      {GLFW_KEY_Y, false, Action::kRedo, "", "", true},
      {GLFW_KEY_ESCAPE, true, Action::kQuit, "Shift+Esc", "quit (asks first when there are unsaved changes)"},
  };
  return table;
}

namespace {

struct KeyPress {
  int key, mods;
  bool repeat;
};

// Filled by the window's key callback during the event poll, emptied by pressed_actions(). Main
// thread only (GLFW calls back on the thread that polls).
std::vector<KeyPress>& key_presses() {
  static std::vector<KeyPress> presses;
  return presses;
}

static_assert(HeldModifiers::kShift == GLFW_MOD_SHIFT && HeldModifiers::kCtrl == GLFW_MOD_CONTROL);

HeldModifiers& held_modifiers() {
  static HeldModifiers held;  // main thread only, as the key presses
  return held;
}

// The modifier key a GLFW key code is, if any.
bool modifier_key(int key, HeldModifiers::Key* which) {
  switch (key) {
    case GLFW_KEY_LEFT_SHIFT: *which = HeldModifiers::kLeftShift; return true;
    case GLFW_KEY_RIGHT_SHIFT: *which = HeldModifiers::kRightShift; return true;
    case GLFW_KEY_LEFT_CONTROL: *which = HeldModifiers::kLeftCtrl; return true;
    case GLFW_KEY_RIGHT_CONTROL: *which = HeldModifiers::kRightCtrl; return true;
    default: return false;
  }
}

DoubleClickDetector& double_clicks() {
  static DoubleClickDetector detector;  // main thread only, as the key presses
  return detector;
}

}  // namespace

void begin_mouse_poll(double busy_s) { double_clicks().begin_poll(busy_s); }
void record_left_press(double t_s, double x_px, double y_px) { double_clicks().press(t_s, x_px, y_px); }
bool mouse_double_clicked() { return double_clicks().double_clicked(); }

void record_key_event(int key, int action, int mods) {
  HeldModifiers::Key which;
  if (modifier_key(key, &which)) {
    if (action == GLFW_RELEASE)
      held_modifiers().release(which);
    else
      held_modifiers().press(which);
    return;
  }
  if (action == GLFW_PRESS || action == GLFW_REPEAT)
    key_presses().push_back({key, mods | held_modifiers().mods(), action == GLFW_REPEAT});
}
void clear_key_presses() { key_presses().clear(); }

bool take_enter_press() {
  auto& presses = key_presses();
  const auto is_enter = [](const KeyPress& p) { return p.key == GLFW_KEY_ENTER || p.key == GLFW_KEY_KP_ENTER; };
  const auto it = std::find_if(presses.begin(), presses.end(), is_enter);
  if (it == presses.end()) return false;
  presses.erase(it);
  return true;
}

// From the recorded presses, not ImGui::IsKeyPressed: ImGui 1.86 keeps only whether a key is down at
// NewFrame, so a tap whose press and release fall in one event poll (a slow frame, a quick tap, a
// scripted key) was lost. A press's modifiers are those down when it was made (record_key_event), not
// those ImGui sees held at NewFrame: "PgUp, Ctrl+S" in one poll is a nudge and a save.
std::vector<Action> pressed_actions() {
  std::vector<Action> actions;
  // Every bound press is taken; the others (Enter) stay for the dialog or text field drawn after this call.
  std::vector<KeyPress> presses;
  auto& recorded = key_presses();
  const auto bound = [](const KeyPress& p) {
    return std::any_of(key_table().begin(), key_table().end(), [&](const KeyBinding& k) { return k.key == p.key; });
  };
  std::copy_if(recorded.begin(), recorded.end(), std::back_inserter(presses), bound);
  recorded.erase(std::remove_if(recorded.begin(), recorded.end(), bound), recorded.end());
  // While a text field has the keyboard or an item is held, plain keys are typing; with the pointer outside the
  // window (a mis-click elsewhere, then typing: P wrote PNGs) they are not for us (gl_window.cpp forgets such a
  // pointer). Ctrl chords (Ctrl+S) still act: a save must not depend on where the focus is.
  const bool typing = ImGui::GetIO().WantTextInput || ImGui::IsAnyItemActive() || !ImGui::IsMousePosValid();
  for (const KeyPress& p : presses) {
    const bool shift = (p.mods & GLFW_MOD_SHIFT) != 0;
    const bool ctrl = (p.mods & GLFW_MOD_CONTROL) != 0;
    for (const KeyBinding& k : key_table())
      // A Ctrl chord's Shift is exact (Ctrl+Z undoes, Ctrl+Shift+Z redoes); plain keys ignore a Shift not asked for.
      if (k.key == p.key && (!p.repeat || !k.ctrl) && (k.ctrl ? k.shift == shift : (!k.shift || shift)) &&
          k.ctrl == ctrl && (!typing || k.ctrl))
        actions.push_back(k.action);
  }
  return actions;
}

void draw_help_overlay(bool* open) {
  if (!*open) return;
  const ImGuiViewport* vp = ImGui::GetMainViewport();
  ImGui::SetNextWindowPos(ImVec2(vp->Pos.x + vp->Size.x / 2, vp->Pos.y + vp->Size.y / 2), ImGuiCond_Always,
                          ImVec2(0.5f, 0.5f));
  ImGui::SetNextWindowBgAlpha(0.92f);
  if (ImGui::Begin("Keys and mouse", open, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoCollapse)) {
    if (ImGui::BeginTable("keys", 2, ImGuiTableFlags_RowBg | ImGuiTableFlags_BordersInnerV)) {
      for (const KeyBinding& k : key_table()) {
        if (k.help[0] == '\0') continue;  // an alias shown with its main key
        ImGui::TableNextRow();
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(k.keys);
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(k.help);
      }
      const char* mouse[][2] = {{"drag indenter", "move it in the pad plane"},
                                {"Shift+drag", "push in / pull out"},
                                {"Ctrl+drag", "twist about the pad normal"},
                                {"Alt+drag", "tilt (x) and roll (y)"},
                                {"drag elsewhere", "orbit; middle: pan; right / wheel: zoom"},
                                {"click a model's field", "colour the 3D view's markers by its |d|"},
                                {"double-click a field", "enlarge that panel to the whole field area / back"},
                                {"hover a marker", "its (du, dv) in every model and the measurement"}};
      for (auto& m : mouse) {
        ImGui::TableNextRow();
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(m[0]);
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(m[1]);
      }
      ImGui::EndTable();
    }
  }
  ImGui::End();
}

}  // namespace sb::ui
