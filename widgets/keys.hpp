#pragma once
// The one table of keyboard shortcuts: the workbench dispatches through it and the help overlay (F1 / H)
// is generated from it, so the two never disagree.
#include <string>
#include <vector>

namespace sb::ui {

enum class Action {
  PlayPause, StepForward, StepBack, Rewind, End,
  NudgeXPlus, NudgeXMinus, NudgeYPlus, NudgeYMinus, PushIn, PullOut, TwistPlus, TwistMinus,
  CameraReset, CameraTop, CameraSide, CameraIso,
  ArrowsLonger, ArrowsShorter, NextMarkerModel,
  Screenshot, ToggleHelp, SaveSession, Quit,
};

struct KeyBinding {
  int key;            // GLFW key code
  bool shift;         // Shift must be held (finer nudges ignore it: see description)
  Action action;
  const char* keys;   // as shown in the help overlay
  const char* help;
  bool ctrl = false;  // Ctrl must be held
};

const std::vector<KeyBinding>& key_table();
// The actions whose keys were pressed since the last call (ignored while a text field has the
// keyboard). The presses come from record_key_press, which the window's GLFW key callback calls;
// clear_key_presses drops the ones nobody asked for (GlWindow::begin_frame, before polling).
std::vector<Action> pressed_actions();
void record_key_press(int key, int mods, bool repeat);
void clear_key_presses();
void draw_help_overlay(bool* open);

}  // namespace sb::ui
