#pragma once
// How a field panel draws a real sensor frame under its arrows, and the colour maps the arrows are coloured
// by, without a window (widgets/field_panel draws them). A real TacTip frame is white pins on black: thin
// arrows in the colours of the pins read as part of the image, so by default the frame is dimmed.
#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace sb {

// What sits under a panel's arrows when the step has a real frame (a neutral gel image is never changed).
enum class FrameBackdrop {
  kDimmed,    // the frame at kDimmedFrameBrightness: the arrows stand out (the default)
  kOutlined,  // the frame as recorded, every arrow drawn over a dark outline
  kRaw,       // the frame as recorded, the arrows as they are
};
inline constexpr std::array<FrameBackdrop, 3> kFrameBackdrops{FrameBackdrop::kDimmed, FrameBackdrop::kOutlined,
                                                              FrameBackdrop::kRaw};
// The dimmed frame's brightness (a fraction of the recorded one): the pins' white becomes a dark grey that
// the colour maps' bright ends stand out of, while the pins stay visible.
inline constexpr double kDimmedFrameBrightness = 0.35;

// "dimmed frame", "outlined arrows", "raw frame" (the panel's button and its tooltip).
std::string backdrop_name(FrameBackdrop b);
// The next choice in kFrameBackdrops order (the panel's button cycles).
FrameBackdrop next_backdrop(FrameBackdrop b);
// The factor every channel of the frame is multiplied by: kDimmedFrameBrightness for kDimmed over a real
// frame, else 1 (the neutral gel image of a scene keeps its look).
double backdrop_brightness(FrameBackdrop b, bool real_frame);
// An 8-bit channel of the frame as drawn (rounded). @pre 0 <= brightness <= 1.
int dimmed_channel(int channel, double brightness);

// Each panel's choice by its title; a panel never chosen for is kDimmed.
class PanelBackdrops {
 public:
  FrameBackdrop of(const std::string& panel) const;
  void set(const std::string& panel, FrameBackdrop b);
  void cycle(const std::string& panel) { set(panel, next_backdrop(of(panel))); }
  // Every choice made, in the order first made (what a session file keeps); assign() replaces them all.
  const std::vector<std::pair<std::string, FrameBackdrop>>& chosen() const { return chosen_; }
  void assign(std::vector<std::pair<std::string, FrameBackdrop>> chosen) { chosen_ = std::move(chosen); }

 private:
  std::vector<std::pair<std::string, FrameBackdrop>> chosen_;
};

// The colour maps of |d| (shared by the field panels and the 3D view's markers).
enum class ColourMap {
  kViridis,       // perceptual, dark violet to yellow: the default (reads on the neutral gel and a dimmed frame)
  kHighContrast,  // saturated and dark throughout, blue to red to orange: reads on a raw frame's white pins
};
inline constexpr std::array<ColourMap, 2> kColourMaps{ColourMap::kViridis, ColourMap::kHighContrast};
struct Rgb {
  double r = 0, g = 0, b = 0;  // each in [0, 1]
};
// "viridis", "high contrast" (the Display section's combo).
std::string colour_map_name(ColourMap m);
// The colour of `t` (|d| / colour max) on map `m`: piecewise linear between the map's stops, t clamped to
// [0, 1] (NaN: 0).
Rgb colour_of(ColourMap m, double t);
// Rec. 709 relative luminance of a colour (linear weights on the channels as stored: a contrast measure).
double luminance(const Rgb& c);

// The outline drawn under an arrow of colour `arrow`, wider than it, over a real frame: for kOutlined a dark one
// (the raw frame's white pins); for kDimmed one that contrasts with the arrow, light under a dark arrow (viridis's
// low end on the dimmed pins and the black between them) and dark under a light one. None over the gel image of a
// scene, nor for kRaw.
std::optional<Rgb> arrow_outline(FrameBackdrop b, bool real_frame, const Rgb& arrow);
// An arrow at or below this luminance gets the light outline over a dimmed frame.
inline constexpr double kDarkArrowLuminance = 0.35;

}  // namespace sb
