#pragma once
// Which modifiers (Shift, Ctrl) were held at each key press, from the key events in the order they came.
// The shortcuts took a press's modifiers from its event or from ImGui's "held at NewFrame" state; when a
// key and a following Ctrl+S were polled in one frame (a quick typist, a slow frame, the GUI soak of tests/cli/soak.py),
// Ctrl was held at NewFrame and the earlier key counted as Ctrl+key: the nudge was dropped and the save
// lacked it. Here the modifier keys' own presses and releases are replayed in order, so a press carries
// exactly the modifiers that were down when it was made. Left and right keys are counted apart.
namespace sb {

class HeldModifiers {
 public:
  enum Key { kLeftShift, kRightShift, kLeftCtrl, kRightCtrl, kKeys };
  enum Mod { kShift = 1, kCtrl = 2 };  // the bits of mods(), as GLFW_MOD_SHIFT and GLFW_MOD_CONTROL

  void press(Key k) { down_[k] = true; }
  void release(Key k) { down_[k] = false; }
  // The modifiers held now, as kShift | kCtrl bits.
  int mods() const;

 private:
  bool down_[kKeys] = {};
};

}  // namespace sb
