#include <catch2/catch.hpp>
#include <cmath>

#include "core/workbench/field_display.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_field_display {

using namespace sb;

TEST_CASE("off_scale_note speaks only beyond 5x the colour scale", "[field_display]") {
  // The default scene's FOTS at its authors' parameters: 44.17 px on a 1 px colour scale, 44x.
  CHECK(off_scale_note(44.17, 1.0, true) == "field up to 44.2 px,\n44x the colour scale:\narrows clipped");
  CHECK(off_scale_note(44.17, 1.0, false) == "field up to 44.2 px,\n44x the colour scale");
  // 5x exactly is still on the scale; just above it is not.
  CHECK(off_scale_note(5.0, 1.0, true).empty());
  CHECK_FALSE(off_scale_note(5.01, 1.0, true).empty());
  // No scale (0) or no field (NaN): nothing to say.
  CHECK(off_scale_note(10.0, 0.0, true).empty());
  CHECK(off_scale_note(std::nan(""), 1.0, true).empty());
}

TEST_CASE("drawn_arrow scales by the gain and cuts at the longest length, keeping the direction", "[field_display]") {
  constexpr double kTol = 1e-12;
  bool cut = true;
  // (3, 4) px at gain 2 is (6, 8), length 10: under a 15 px cut it stays.
  Vec2 a = drawn_arrow(Vec2(3, 4), 2.0, 15.0, &cut);
  CHECK_FALSE(cut);
  CHECK((a - Vec2(6, 8)).norm() < kTol);
  // Under a 5 px cut it becomes (3, 4): length 5, same direction.
  a = drawn_arrow(Vec2(3, 4), 2.0, 5.0, &cut);
  CHECK(cut);
  CHECK((a - Vec2(3, 4)).norm() < kTol);
  // 0: no cut at all.
  a = drawn_arrow(Vec2(300, 400), 2.0, 0.0, &cut);
  CHECK_FALSE(cut);
  CHECK((a - Vec2(600, 800)).norm() < kTol);
}

}  // namespace test_field_display
