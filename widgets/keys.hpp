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
// The actions whose keys were pressed this frame (ignored while a text field has the keyboard).
std::vector<Action> pressed_actions();
void draw_help_overlay(bool* open);

}  // namespace sb::ui
