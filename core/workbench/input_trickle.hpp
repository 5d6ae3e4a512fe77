#pragma once
// The window's input events in the order they came, handed to the GUI a frame's worth at a time so that no
// press, release or character is lost. ImGui 1.86 reads a key or mouse button only as down or up at a
// frame's start: a tap whose press and release are polled together (a slow frame during a fit or an
// import, a quick click) was never seen by its widgets. take_frame() applies ImGui 1.87's "trickling" rule
// instead: a frame takes events until one would overwrite a change the same frame already made.
#include <cstddef>
#include <deque>
#include <vector>

namespace sb {

struct InputEvent {
  enum class Kind { kKey, kMouseButton, kChar, kCursorPos, kScroll };
  // As GLFW's actions (GLFW_RELEASE, GLFW_PRESS, GLFW_REPEAT); the window checks they agree.
  enum Action { kRelease = 0, kPress = 1, kRepeat = 2 };

  Kind kind = Kind::kKey;
  int code = 0;      // Key: the key code; MouseButton: the button; Char: the Unicode code point
  int scancode = 0;  // Key only
  int action = kPress;
  int mods = 0;         // Key and MouseButton: the modifier bits the event came with
  double x = 0, y = 0;  // CursorPos: the window position (px); Scroll: the offsets
  double t_s = 0;       // when it was polled (the double-click detector's clock)

  static InputEvent key(int key, int scancode, int action, int mods);
  static InputEvent mouse_button(int button, int action, int mods);
  static InputEvent character(unsigned codepoint);
  static InputEvent cursor(double x_px, double y_px);
  static InputEvent scroll(double dx, double dy);
};

class InputTrickle {
 public:
  void push(const InputEvent& event) { queue_.push_back(event); }
  bool empty() const { return queue_.empty(); }
  std::size_t size() const { return queue_.size(); }

  // Removes and returns the longest prefix of the queue that one frame can take without an event hiding
  // another. It stops before: a press or release of a key or button that already changed in this frame;
  // a key change after a button changed or characters were taken; a button change after the cursor moved
  // or the wheel turned; a cursor move after a key or button changed, the wheel turned or characters were
  // taken; a character after a key or button changed or the cursor moved; a scroll after the cursor moved
  // or a button changed. Repeats change nothing and never stop a frame. Never empty while the queue is not.
  std::vector<InputEvent> take_frame();

 private:
  std::deque<InputEvent> queue_;
};

}  // namespace sb
