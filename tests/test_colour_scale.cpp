#include <catch2/catch.hpp>
#include <cmath>

#include "core/workbench/colour_scale.hpp"

// This file's names in a namespace of its own: the unity build compiles several test files as one unit.
namespace test_colour_scale {

using namespace sb;

constexpr double kTol = 1e-12;
constexpr double kPitchPx = 30.0;

TEST_CASE("colour_top is nice_floor, or twice or five times it; the arrow gain draws the largest at 0.9 pitch",
          "[colour_scale]") {
  CHECK(std::abs(colour_top(1.7) - 2.0) < kTol);
  CHECK(std::abs(colour_top(2.0) - 2.0) < kTol);
  // 38: nice_floor 20, twice reaches it -> 40; 0.3: nice_floor 0.2, twice -> 0.4.
  CHECK(std::abs(colour_top(38.0) - 40.0) < kTol);
  CHECK(std::abs(colour_top(0.3) - 0.4) < kTol);
  CHECK(std::abs(nice_floor(38.0) - 20.0) < kTol);
  // 0.9 * 30 / 2 = 13.5; a tiny field is clamped at the slider's 200.
  CHECK(std::abs(auto_arrow_gain(2.0, kPitchPx) - 13.5) < kTol);
  CHECK(auto_arrow_gain(1e-4, kPitchPx) == kMaxArrowGain);
}

TEST_CASE("a 2 px dataset opened after a 40 px one gets its own scale, hold or not", "[colour_scale]") {
  for (const bool hold : {false, true}) {
    ColourScaleKeeper k;
    k.open("big", 38.0, kPitchPx);
    k.set_hold(hold);
    k.at_frame(38.0);
    CHECK(std::abs(k.current().colour_max_px - 40.0) < kTol);
    // Opened before its first step (no field yet): already the small dataset's own, colour_top(1.7) = 2 px,
    // arrows 0.9 * 30 / 1.7 px.
    k.open("small", 1.7, kPitchPx);
    CHECK(std::abs(k.current().colour_max_px - 2.0) < kTol);
    CHECK(std::abs(k.current().arrow_gain - 0.9 * kPitchPx / 1.7) < kTol);
    // A frame without a field keeps it.
    k.at_frame(0.0);
    CHECK(std::abs(k.current().colour_max_px - 2.0) < kTol);
  }
}

TEST_CASE("colours held for a dataset come back with it, and only grow while held", "[colour_scale]") {
  ColourScaleKeeper k;
  k.open("a", 1.7, kPitchPx);
  k.set_hold(true);
  k.at_frame(8.0);  // a drag far past the sample: held at colour_top(8) = 10 px
  CHECK(std::abs(k.current().colour_max_px - 10.0) < kTol);
  k.at_frame(1.0);  // a smaller frame: held colours stay, the arrows follow (0.9 * 30 / 1 = 27)
  CHECK(std::abs(k.current().colour_max_px - 10.0) < kTol);
  CHECK(std::abs(k.current().arrow_gain - 27.0) < kTol);
  k.open("b", 0.4, kPitchPx);
  CHECK(std::abs(k.current().colour_max_px - 0.4) < kTol);  // b's own: colour_top(0.4) = 2 x 0.2
  k.open("a", 1.7, kPitchPx);                               // back to a: the 10 px it held
  CHECK(std::abs(k.current().colour_max_px - 10.0) < kTol);
}

TEST_CASE("without hold colours follow the frame; reset returns the dataset's own default", "[colour_scale]") {
  ColourScaleKeeper k;
  k.open("a", 1.7, kPitchPx);
  k.set_hold(false);
  CHECK_FALSE(k.hold());
  k.at_frame(8.0);
  CHECK(std::abs(k.current().colour_max_px - 10.0) < kTol);
  k.at_frame(0.3);
  CHECK(std::abs(k.current().colour_max_px - 0.4) < kTol);
  const ScaleSetting s = k.reset();
  CHECK(std::abs(s.colour_max_px - 2.0) < kTol);
  CHECK(std::abs(s.arrow_gain - 0.9 * kPitchPx / 1.7) < kTol);
  // A scene (no measurement) resets to the built-in scale.
  k.open("", 0.0, kPitchPx);
  CHECK(std::abs(k.reset().colour_max_px - ScaleSetting{}.colour_max_px) < kTol);
}

}  // namespace test_colour_scale
