// core/workbench/held_modifiers: the modifiers of each key press, from the events in their order.
#include <catch2/catch.hpp>

#include "core/workbench/held_modifiers.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_held_modifiers {

using sb::HeldModifiers;

TEST_CASE("a key pressed before Ctrl in the same poll does not carry Ctrl", "[workbench][keys]") {
  // The soak's "PgUp, then Ctrl+S" typed at once: PgUp down (mods 0), Ctrl down, S down (Ctrl), Ctrl up.
  HeldModifiers h;
  const int at_pgup = h.mods();
  h.press(HeldModifiers::kLeftCtrl);
  const int at_s = h.mods();
  h.release(HeldModifiers::kLeftCtrl);
  CHECK(at_pgup == 0);
  CHECK(at_s == HeldModifiers::kCtrl);
  CHECK(h.mods() == 0);
}

TEST_CASE("left and right modifier keys are held apart", "[workbench][keys]") {
  HeldModifiers h;
  h.press(HeldModifiers::kLeftShift);
  h.press(HeldModifiers::kRightShift);
  h.release(HeldModifiers::kLeftShift);  // the right one is still down
  CHECK(h.mods() == HeldModifiers::kShift);
  h.press(HeldModifiers::kRightCtrl);
  CHECK(h.mods() == (HeldModifiers::kShift | HeldModifiers::kCtrl));
  h.release(HeldModifiers::kRightShift);
  h.release(HeldModifiers::kRightCtrl);
  CHECK(h.mods() == 0);
}

}  // namespace test_held_modifiers
