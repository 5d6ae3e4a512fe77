#include "core/workbench/input_trickle.hpp"

#include <catch2/catch.hpp>
#include <string>
#include <vector>

// This file's names in a namespace of its own: the unity build compiles several test files as one unit.
namespace test_input_trickle {

using sb::InputEvent;
using sb::InputTrickle;

constexpr int kCtrl = 341;       // GLFW_KEY_LEFT_CONTROL
constexpr int kA = 65;           // GLFW_KEY_A
constexpr int kEnd = 269;        // GLFW_KEY_END
constexpr int kBackspace = 259;  // GLFW_KEY_BACKSPACE
constexpr int kLeft = 0;         // GLFW_MOUSE_BUTTON_LEFT
constexpr int kModCtrl = 2;      // GLFW_MOD_CONTROL

InputEvent press(int key, int mods = 0) { return InputEvent::key(key, 0, InputEvent::kPress, mods); }
InputEvent release(int key, int mods = 0) { return InputEvent::key(key, 0, InputEvent::kRelease, mods); }
InputEvent down(int button) { return InputEvent::mouse_button(button, InputEvent::kPress, 0); }
InputEvent up(int button) { return InputEvent::mouse_button(button, InputEvent::kRelease, 0); }

// Each frame as a word: k+65 / k-65 a key's press / release, kr65 a repeat, b+0 / b-0 a button, c'a' a
// character, m a cursor move, s a scroll; events of one frame joined by spaces.
std::string describe(const InputEvent& e) {
  const char* act = e.action == InputEvent::kPress ? "+" : e.action == InputEvent::kRelease ? "-" : "r";
  switch (e.kind) {
    case InputEvent::Kind::kKey: return "k" + std::string(act) + std::to_string(e.code);
    case InputEvent::Kind::kMouseButton: return "b" + std::string(act) + std::to_string(e.code);
    case InputEvent::Kind::kChar: return "c'" + std::string(1, static_cast<char>(e.code)) + "'";
    case InputEvent::Kind::kCursorPos: return "m";
    case InputEvent::Kind::kScroll: return "s";
  }
  return "?";
}

std::vector<std::string> frames(InputTrickle& q) {
  std::vector<std::string> out;
  while (!q.empty()) {
    std::string f;
    for (const InputEvent& e : q.take_frame()) f += (f.empty() ? "" : " ") + describe(e);
    out.push_back(f);
  }
  return out;
}

TEST_CASE("a key's press and release polled together land in two frames", "[input_trickle]") {
  InputTrickle q;
  q.push(press(kEnd));
  q.push(release(kEnd));
  // The release would undo the press in the frame that took it: it starts the next frame.
  CHECK(frames(q) == std::vector<std::string>{"k+269", "k-269"});
  CHECK(q.take_frame().empty());
}

TEST_CASE("ten clicks polled together are twenty frames", "[input_trickle]") {
  InputTrickle q;
  q.push(InputEvent::cursor(300, 200));
  for (int i = 0; i < 10; ++i) {
    q.push(down(kLeft));
    q.push(up(kLeft));
  }
  // The move first (a button change after a move waits: the widget under the cursor is hovered first), then
  // each press and each release in a frame of its own: the left button changes once per frame.
  const std::vector<std::string> got = frames(q);
  REQUIRE(got.size() == 21);
  CHECK(got[0] == "m");
  for (int i = 0; i < 10; ++i) {
    CHECK(got[1 + 2 * i] == "b+0");
    CHECK(got[2 + 2 * i] == "b-0");
  }
}

TEST_CASE("typed text and the Backspaces after it keep their order", "[input_trickle]") {
  InputTrickle q;
  for (char c : std::string("abc")) {
    const int key = 'A' + (c - 'a');
    q.push(press(key));
    q.push(InputEvent::character(static_cast<unsigned>(c)));
    q.push(release(key));
  }
  for (int i = 0; i < 3; ++i) {
    q.push(press(kBackspace));
    q.push(release(kBackspace));
  }
  // By hand: a character never joins a frame in which a key changed, and a key change never follows a
  // character: "k+65 | c'a' | k-65 k+66 | c'b' | k-66 k+67 | c'c' | k-67 k+259 | k-259 | k+259 | ...". The
  // release of C and the first Backspace's press share a frame (two different keys).
  CHECK(frames(q) == std::vector<std::string>{"k+65", "c'a'", "k-65 k+66", "c'b'", "k-66 k+67", "c'c'", "k-67 k+259",
                                              "k-259", "k+259", "k-259", "k+259", "k-259"});
}

TEST_CASE("Ctrl stays held while a key taps under it", "[input_trickle]") {
  InputTrickle q;
  q.push(press(kCtrl));
  q.push(press(kA, kModCtrl));
  q.push(release(kA, kModCtrl));
  q.push(release(kCtrl));
  q.push(press(kEnd));
  q.push(release(kEnd));
  // Frame 1: Ctrl down and A down (two keys): ImGui sees Ctrl+A pressed. A's release starts frame 2, which also
  // takes Ctrl's release and End's press (three different keys): End without Ctrl. End's release: frame 3.
  CHECK(frames(q) == std::vector<std::string>{"k+341 k+65", "k-65 k-341 k+269", "k-269"});
}

TEST_CASE("a Ctrl+click keeps Ctrl down on the press's frame", "[input_trickle]") {
  InputTrickle q;
  q.push(press(kCtrl));
  q.push(down(kLeft));
  q.push(up(kLeft));
  q.push(release(kCtrl));
  // Frame 1: Ctrl then the press (a button after a key fits). The release: the button changed; frame 2. Ctrl's
  // release after a button change: frame 3.
  CHECK(frames(q) == std::vector<std::string>{"k+341 b+0", "b-0", "k-341"});
}

TEST_CASE("repeats never split a frame, moves merge until a button changes", "[input_trickle]") {
  InputTrickle q;
  q.push(press(kBackspace));
  q.push(InputEvent::key(kBackspace, 0, InputEvent::kRepeat, 0));
  q.push(InputEvent::key(kBackspace, 0, InputEvent::kRepeat, 0));
  q.push(release(kBackspace));
  q.push(InputEvent::cursor(1, 1));
  q.push(InputEvent::cursor(2, 2));
  q.push(down(kLeft));
  q.push(InputEvent::cursor(3, 3));
  q.push(up(kLeft));
  q.push(InputEvent::scroll(0, 1));
  q.push(InputEvent::scroll(0, 1));
  // By hand: press + two repeats (no change); the release is a second change of Backspace: frame 2. A move
  // after a key change waits: frame 3 takes both moves. The press after moves: frame 4; the move
  // after a button change: frame 5; the release after a move: frame 6; a scroll after a button change: frame
  // 7 takes both scrolls (the wheel turning twice is one turn of two notches).
  CHECK(frames(q) == std::vector<std::string>{"k+259 kr259 kr259", "k-259", "m m", "b+0", "m", "b-0", "s s"});
}

TEST_CASE("an event keeps what it came with", "[input_trickle]") {
  InputTrickle q;
  InputEvent e = InputEvent::key(kA, 38, InputEvent::kPress, kModCtrl);
  e.t_s = 12.5;
  q.push(e);
  q.push(InputEvent::cursor(10.5, 20.25));
  const std::vector<InputEvent> f1 = q.take_frame();
  REQUIRE(f1.size() == 1);
  CHECK(f1[0].scancode == 38);
  CHECK(f1[0].mods == kModCtrl);
  CHECK(f1[0].t_s == 12.5);
  const std::vector<InputEvent> f2 = q.take_frame();
  REQUIRE(f2.size() == 1);
  CHECK(f2[0].x == 10.5);
  CHECK(f2[0].y == 20.25);
  CHECK(q.empty());
}

}  // namespace test_input_trickle
