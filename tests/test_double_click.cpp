#include "core/workbench/double_click.hpp"

#include <catch2/catch.hpp>

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_double_click {

using sb::DoubleClickDetector;

// Presses are fed as the window's event poll delivers them: begin_poll(busy) once per frame (busy: the
// work of the frame before that poll), then the presses that poll delivered, each with its poll time.
// A double-click: two presses within 6 px whose poll times, less the busy time before the second, are
// within 0.50 s (kMaxGapS).
TEST_CASE("two quick presses at one place are a double-click", "[double_click]") {
  DoubleClickDetector d;
  d.begin_poll(0.02);
  d.press(10.00, 100, 100);
  CHECK_FALSE(d.double_clicked());
  d.begin_poll(0.02);
  d.press(10.15, 101, 100);  // 0.15 - 0.02 = 0.13 s after, 1 px away
  CHECK(d.double_clicked());
  d.begin_poll(0.02);
  CHECK_FALSE(d.double_clicked());  // reported for the poll that delivered it only
}

TEST_CASE("a slow frame does not break a double-click", "[double_click]") {
  DoubleClickDetector d;
  // The first press ends an idle wait (polled at once); its release wakes a short frame; then a frame busy
  // for 0.45 s holds the second press, made 0.15 s after the first: polled at 10.5, 0.5 s after the first.
  d.begin_poll(0.02);
  d.press(10.0, 50, 60);
  d.begin_poll(0.03);  // the release's poll: no press
  d.begin_poll(0.45);
  d.press(10.5, 50, 60);  // 10.5 - 0.45 - 10.0 = 0.05 s <= 0.50
  CHECK(d.double_clicked());
  // Both presses delivered by one poll (the whole double-click during one frame) also count.
  d.begin_poll(1.0);
  d.press(21.5, 50, 60);
  d.press(21.5, 50, 60);
  CHECK(d.double_clicked());
}

TEST_CASE("presses far apart in time or space are two clicks", "[double_click]") {
  DoubleClickDetector d;
  d.begin_poll(0.02);
  d.press(30.0, 10, 10);
  d.begin_poll(0.05);
  d.press(30.6, 10, 10);  // 30.6 - 0.05 - 30.0 = 0.55 s > 0.50
  CHECK_FALSE(d.double_clicked());
  d.begin_poll(0.02);
  d.press(30.7, 17, 10);  // 0.08 s after the last, but 7 px away (> 6 px)
  CHECK_FALSE(d.double_clicked());
  d.begin_poll(0.02);
  d.press(30.8, 17, 10);  // completes a double-click with the press before
  CHECK(d.double_clicked());
  d.begin_poll(0.02);
  d.press(30.9, 17, 10);  // a third press starts a new pair; it is not a second double-click
  CHECK_FALSE(d.double_clicked());
}

}  // namespace test_double_click
