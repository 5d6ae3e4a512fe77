// core/workbench/column_layout: the left column's width from the window and the user's drag of the divider.
#include <catch2/catch.hpp>

#include "core/workbench/column_layout.hpp"

namespace test_column_layout {

TEST_CASE("never dragged, the left column is a quarter of the window within 300 and 400 px", "[column_layout]") {
  CHECK(sb::left_column_px(1280, 0) == 320);  // 1280 / 4
  CHECK(sb::left_column_px(1920, 0) == 400);  // 480 capped at 400
  CHECK(sb::left_column_px(1000, 0) == 300);  // 250 raised to 300
}

TEST_CASE("a dragged divider is kept, leaving the right column at least 480 px", "[column_layout]") {
  CHECK(sb::left_column_px(1280, 560) == 560);  // what the user asked: the tables' columns read whole
  CHECK(sb::left_column_px(1280, 900) == 800);  // 1280 - 480
  CHECK(sb::left_column_px(1280, 120) == 300);  // never narrower than the labels need
  CHECK(sb::left_column_px(700, 500) == 300);   // 700 - 480 = 220 < 300: the minimum wins
}

}  // namespace test_column_layout
