#include <catch2/catch.hpp>
#include <cmath>

#include "core/workbench/frame_backdrop.hpp"

// This file's names in a namespace of its own: the unity build compiles several test files as one unit.
namespace test_frame_backdrop {

using namespace sb;

constexpr double kTol = 1e-12;

TEST_CASE("a real frame is dimmed by default, outlined or raw on request; the gel image never", "[frame_backdrop]") {
  PanelBackdrops panels;
  CHECK(panels.of("HydroShear") == FrameBackdrop::kDimmed);
  CHECK(backdrop_brightness(FrameBackdrop::kDimmed, true) == kDimmedFrameBrightness);
  // A scene's neutral gel image is no recorded frame: drawn as it is, no outline.
  CHECK(backdrop_brightness(FrameBackdrop::kDimmed, false) == 1.0);
  const Rgb violet = colour_of(ColourMap::kViridis, 0.0);
  CHECK_FALSE(arrow_outline(FrameBackdrop::kOutlined, false, violet));
  CHECK_FALSE(arrow_outline(FrameBackdrop::kDimmed, false, violet));
  CHECK(backdrop_brightness(FrameBackdrop::kOutlined, true) == 1.0);
  CHECK(arrow_outline(FrameBackdrop::kOutlined, true, violet));
  CHECK(backdrop_brightness(FrameBackdrop::kRaw, true) == 1.0);
  CHECK_FALSE(arrow_outline(FrameBackdrop::kRaw, true, violet));
}

TEST_CASE("over a dimmed frame an arrow's outline contrasts with it; over a raw one it is dark", "[frame_backdrop]") {
  // viridis at 0 is (0.267, 0.005, 0.329): luminance 0.2126 * 0.267 + 0.7152 * 0.005 + 0.0722 * 0.329 = 0.084,
  // dark; at 1 (0.993, 0.906, 0.144): 0.2111 + 0.6480 + 0.0104 = 0.870, light.
  const Rgb dark = colour_of(ColourMap::kViridis, 0.0), light = colour_of(ColourMap::kViridis, 1.0);
  CHECK(luminance(dark) == Approx(0.084).margin(1e-3));
  CHECK(luminance(light) == Approx(0.870).margin(1e-3));
  const auto under_dark = arrow_outline(FrameBackdrop::kDimmed, true, dark);
  const auto under_light = arrow_outline(FrameBackdrop::kDimmed, true, light);
  REQUIRE(under_dark);
  REQUIRE(under_light);
  CHECK(luminance(*under_dark) > 1 - kDarkArrowLuminance);                        // light under the dark arrow
  CHECK(luminance(*under_light) < kDarkArrowLuminance);                           // dark under the light one
  CHECK(luminance(*arrow_outline(FrameBackdrop::kOutlined, true, dark)) == 0.0);  // the raw frame's white pins
}

TEST_CASE("each panel keeps its own choice; the button cycles dimmed, outlined, raw", "[frame_backdrop]") {
  PanelBackdrops panels;
  panels.cycle("FOTS");
  CHECK(panels.of("FOTS") == FrameBackdrop::kOutlined);
  CHECK(panels.of("HydroShear") == FrameBackdrop::kDimmed);  // another panel is untouched
  panels.cycle("FOTS");
  CHECK(panels.of("FOTS") == FrameBackdrop::kRaw);
  panels.cycle("FOTS");
  CHECK(panels.of("FOTS") == FrameBackdrop::kDimmed);
  panels.set("Measured", FrameBackdrop::kRaw);
  CHECK(panels.of("Measured") == FrameBackdrop::kRaw);
  CHECK(backdrop_name(FrameBackdrop::kOutlined) == "outlined arrows");
}

TEST_CASE("dimming multiplies each channel and rounds", "[frame_backdrop]") {
  // A white pin (255) at 35 %: 255 * 0.35 = 89.25 -> 89; black stays black; 100 * 0.35 = 35.
  CHECK(dimmed_channel(255, kDimmedFrameBrightness) == 89);
  CHECK(dimmed_channel(0, kDimmedFrameBrightness) == 0);
  CHECK(dimmed_channel(100, kDimmedFrameBrightness) == 35);
  CHECK(dimmed_channel(200, 1.0) == 200);
}

TEST_CASE("the colour maps run through their stops and clamp", "[frame_backdrop]") {
  // Viridis' ends are matplotlib's (0.267, 0.005, 0.329) and (0.993, 0.906, 0.144); halfway between its
  // 0.25 and 0.5 stops, t = 0.375, is their mean: ((0.229 + 0.128) / 2, (0.322 + 0.567) / 2, (0.546 + 0.551) / 2).
  const Rgb lo = colour_of(ColourMap::kViridis, -1.0);
  CHECK(std::abs(lo.r - 0.267) < kTol);
  CHECK(std::abs(lo.b - 0.329) < kTol);
  const Rgb hi = colour_of(ColourMap::kViridis, 7.0);
  CHECK(std::abs(hi.g - 0.906) < kTol);
  const Rgb mid = colour_of(ColourMap::kViridis, 0.375);
  CHECK(std::abs(mid.r - 0.1785) < kTol);
  CHECK(std::abs(mid.g - 0.4445) < kTol);
  CHECK(std::abs(mid.b - 0.5485) < kTol);
  CHECK(std::abs(colour_of(ColourMap::kViridis, std::nan("")).r - 0.267) < kTol);
  CHECK(colour_map_name(ColourMap::kHighContrast) == "high contrast");
}

TEST_CASE("the high-contrast map stays dark enough to read on white pins; viridis' top does not", "[frame_backdrop]") {
  // White (luminance 1) against a colour of luminance L: at most 0.33 leaves a contrast of at least 0.67
  // everywhere on the map. Viridis' yellow top, 0.2126 * 0.993 + 0.7152 * 0.906 + 0.0722 * 0.144 = 0.8695,
  // nearly vanishes on a pin.
  constexpr double kMaxLuminanceOnWhite = 0.33;
  for (int i = 0; i <= 100; ++i)
    CHECK(luminance(colour_of(ColourMap::kHighContrast, i / 100.0)) <= kMaxLuminanceOnWhite);
  CHECK(std::abs(luminance(colour_of(ColourMap::kViridis, 1.0)) - 0.8694798) < 1e-6);
}

}  // namespace test_frame_backdrop
