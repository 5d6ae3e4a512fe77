#include "core/workbench/double_click.hpp"

#include <catch2/catch.hpp>

using sb::DoubleClickDetector;

// Presses are fed as the window's event poll delivers them: begin_poll() once per frame, then the
// presses that frame's poll delivered, each with its poll time.
TEST_CASE("two quick presses at one place are a double-click", "[double_click]") {
  DoubleClickDetector d;
  d.begin_poll();
  d.press(10.00, 100, 100);
  CHECK_FALSE(d.double_clicked());
  d.begin_poll();
  d.press(10.15, 101, 100);   // 0.15 s later, 1 px away: within 0.30 s and 6 px
  CHECK(d.double_clicked());
  d.begin_poll();
  CHECK_FALSE(d.double_clicked());   // reported for the poll that delivered it only
}

TEST_CASE("a slow frame does not break a double-click", "[double_click]") {
  DoubleClickDetector d;
  // Frames of 0.5 s: the user's presses 0.15 s apart reach the program in consecutive polls 0.5 s apart.
  d.begin_poll();
  d.press(20.0, 50, 60);
  d.begin_poll();
  d.press(20.5, 50, 60);
  CHECK(d.double_clicked());
  // Both presses in one poll (the whole double-click during one frame) also count.
  d.begin_poll();
  d.press(21.5, 50, 60);
  d.press(21.5, 50, 60);
  CHECK(d.double_clicked());
}

TEST_CASE("presses far apart in time or space are two clicks", "[double_click]") {
  DoubleClickDetector d;
  d.begin_poll();
  d.press(30.0, 10, 10);
  d.begin_poll();
  d.begin_poll();            // a poll between them with nothing in it: the two are > one frame apart
  d.press(30.4, 10, 10);     // and 0.4 s > 0.30 s
  CHECK_FALSE(d.double_clicked());
  d.begin_poll();
  d.press(30.5, 17, 10);     // 0.1 s after the last, but 7 px away (> 6 px)
  CHECK_FALSE(d.double_clicked());
  d.begin_poll();
  d.press(30.6, 17, 10);     // completes a double-click with the press before
  CHECK(d.double_clicked());
  d.begin_poll();
  d.press(30.7, 17, 10);     // a third press starts a new pair; it is not a second double-click
  CHECK_FALSE(d.double_clicked());
}
