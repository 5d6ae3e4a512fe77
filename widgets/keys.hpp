#pragma once
// The one table of keyboard shortcuts: the workbench dispatches through it and the help overlay (F1 / H)
// is generated from it, so the two never disagree.
#include <string>
#include <vector>

namespace sb::ui {

enum class Action {
  kPlayPause,
  kStepForward,
  kStepBack,
  kRewind,
  kEnd,
  kNudgeXPlus,
  kNudgeXMinus,
  kNudgeYPlus,
  kNudgeYMinus,
  kPushIn,
  kPullOut,
  kTwistPlus,
  kTwistMinus,
  kCameraReset,
  kCameraTop,
  kCameraSide,
  kCameraIso,
  kArrowsLonger,
  kArrowsShorter,
  kNextMarkerModel,
  kScreenshot,
  kToggleHelp,
  kSaveSession,
  kUndo,
  kRedo,
  kQuit,
};

struct KeyBinding {
  int key;     // GLFW key code
  bool shift;  // Shift must be held (finer nudges ignore it: see description)
  Action action;
  const char* keys;  // as shown in the help overlay
  const char* help;
  bool ctrl = false;  // Ctrl must be held
};

const std::vector<KeyBinding>& key_table();
// The actions whose keys were pressed since the last call (while a text field has the keyboard only the
// Ctrl chords), taking those presses; presses of unbound keys (Enter) stay for take_enter_press. The presses come from
// record_key_event, which the window's GLFW key callback calls; clear_key_presses drops the ones nobody asked for
// (GlWindow::begin_frame, before polling).
std::vector<Action> pressed_actions();
// Every key event of the window (GLFW key, action, mods), in order: modifier keys update what is held,
// presses and repeats are recorded with the modifiers held then.
void record_key_event(int key, int action, int mods);
void clear_key_presses();
// Whether Enter (either one) was pressed since the last frame, taking that press: a dialog's default answer.
bool take_enter_press();
// Double-clicks of the left button, from the window's mouse events (core/workbench/double_click.hpp: a
// slow frame does not break them). begin_mouse_poll(busy_s) before each event poll (busy_s: the frame's
// work since the last poll, without the wait for events), record_left_press from the
// GLFW mouse-button callback; mouse_double_clicked says whether this frame's poll completed one.
void begin_mouse_poll(double busy_s);
void record_left_press(double t_s, double x_px, double y_px);
bool mouse_double_clicked();
void draw_help_overlay(bool* open);

}  // namespace sb::ui
