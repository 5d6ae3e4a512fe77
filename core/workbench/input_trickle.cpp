#include "core/workbench/input_trickle.hpp"

#include <set>

namespace sb {

InputEvent InputEvent::key(int key, int scancode, int action, int mods) {
  InputEvent e;
  e.kind = Kind::kKey;
  e.code = key;
  e.scancode = scancode;
  e.action = action;
  e.mods = mods;
  return e;
}

InputEvent InputEvent::mouse_button(int button, int action, int mods) {
  InputEvent e;
  e.kind = Kind::kMouseButton;
  e.code = button;
  e.action = action;
  e.mods = mods;
  return e;
}

InputEvent InputEvent::character(unsigned codepoint) {
  InputEvent e;
  e.kind = Kind::kChar;
  e.code = static_cast<int>(codepoint);
  return e;
}

InputEvent InputEvent::cursor(double x_px, double y_px) {
  InputEvent e;
  e.kind = Kind::kCursorPos;
  e.x = x_px;
  e.y = y_px;
  return e;
}

InputEvent InputEvent::scroll(double dx, double dy) {
  InputEvent e;
  e.kind = Kind::kScroll;
  e.x = dx;
  e.y = dy;
  return e;
}

namespace {

// What the events taken so far in one frame changed: the state each trickling rule asks about.
struct TrickleFrame {
  std::set<int> keys_changed, buttons_changed;
  bool moved = false, wheeled = false, typed = false;

  // Whether `e` still fits into this frame; if it does, records what it changes.
  bool take(const InputEvent& e) {
    const bool changes = e.action != InputEvent::kRepeat;
    switch (e.kind) {
      case InputEvent::Kind::kKey:
        if (!changes) return true;
        if (keys_changed.count(e.code) != 0 || !buttons_changed.empty() || typed) return false;
        keys_changed.insert(e.code);
        return true;
      case InputEvent::Kind::kMouseButton:
        if (!changes) return true;
        if (buttons_changed.count(e.code) != 0 || moved || wheeled) return false;
        buttons_changed.insert(e.code);
        return true;
      case InputEvent::Kind::kChar:
        if (!keys_changed.empty() || !buttons_changed.empty() || moved || wheeled) return false;
        typed = true;
        return true;
      case InputEvent::Kind::kCursorPos:
        if (!keys_changed.empty() || !buttons_changed.empty() || wheeled || typed) return false;
        moved = true;
        return true;
      case InputEvent::Kind::kScroll:
        if (moved || !buttons_changed.empty()) return false;
        wheeled = true;
        return true;
    }
    return false;
  }
};

}  // namespace

std::vector<InputEvent> InputTrickle::take_frame() {
  std::vector<InputEvent> frame;
  TrickleFrame changed;
  // The first event always fits: nothing has changed yet.
  while (!queue_.empty() && changed.take(queue_.front())) {
    frame.push_back(queue_.front());
    queue_.pop_front();
  }
  return frame;
}

}  // namespace sb
