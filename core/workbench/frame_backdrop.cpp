#include "core/workbench/frame_backdrop.hpp"

#include <algorithm>
#include <cmath>

namespace sb {

namespace {
struct Stop {
  double t;
  Rgb c;
};
// Viridis at five points (matplotlib's table at 0, 0.25, 0.5, 0.75, 1).
constexpr std::array<Stop, 5> kViridis{{{0.00, {0.267, 0.005, 0.329}},
                                        {0.25, {0.229, 0.322, 0.546}},
                                        {0.50, {0.128, 0.567, 0.551}},
                                        {0.75, {0.369, 0.789, 0.383}},
                                        {1.00, {0.993, 0.906, 0.144}}}};
// Every stop's luminance stays at or under 0.33, so the whole map reads against white pins (luminance 1).
constexpr std::array<Stop, 4> kHighContrast{
    {{0.00, {0.05, 0.10, 0.75}}, {0.35, {0.55, 0.05, 0.70}}, {0.70, {0.85, 0.05, 0.10}}, {1.00, {0.85, 0.20, 0.00}}}};

template <std::size_t N>
Rgb interpolate(const std::array<Stop, N>& stops, double t) {
  t = std::isnan(t) ? 0.0 : std::clamp(t, 0.0, 1.0);
  std::size_t i = 1;
  while (i + 1 < N && t > stops[i].t) ++i;
  const Stop& a = stops[i - 1];
  const Stop& b = stops[i];
  const double s = (t - a.t) / (b.t - a.t);
  return {a.c.r + s * (b.c.r - a.c.r), a.c.g + s * (b.c.g - a.c.g), a.c.b + s * (b.c.b - a.c.b)};
}
}  // namespace

std::string backdrop_name(FrameBackdrop b) {
  switch (b) {
    case FrameBackdrop::kDimmed: return "dimmed frame";
    case FrameBackdrop::kOutlined: return "outlined arrows";
    case FrameBackdrop::kRaw: return "raw frame";
  }
  return "dimmed frame";
}

FrameBackdrop next_backdrop(FrameBackdrop b) {
  const auto it = std::find(kFrameBackdrops.begin(), kFrameBackdrops.end(), b);
  return it + 1 == kFrameBackdrops.end() ? kFrameBackdrops.front() : *(it + 1);
}

double backdrop_brightness(FrameBackdrop b, bool real_frame) {
  return real_frame && b == FrameBackdrop::kDimmed ? kDimmedFrameBrightness : 1.0;
}

int dimmed_channel(int channel, double brightness) { return static_cast<int>(std::lround(channel * brightness)); }

std::optional<Rgb> arrow_outline(FrameBackdrop b, bool real_frame, const Rgb& arrow) {
  constexpr Rgb kDark{0, 0, 0}, kLight{0.9, 0.9, 0.9};
  if (!real_frame || b == FrameBackdrop::kRaw) return std::nullopt;
  if (b == FrameBackdrop::kOutlined) return kDark;
  return luminance(arrow) <= kDarkArrowLuminance ? kLight : kDark;
}

FrameBackdrop PanelBackdrops::of(const std::string& panel) const {
  for (const auto& [name, b] : chosen_)
    if (name == panel) return b;
  return FrameBackdrop::kDimmed;
}

void PanelBackdrops::set(const std::string& panel, FrameBackdrop b) {
  for (auto& [name, chosen] : chosen_)
    if (name == panel) {
      chosen = b;
      return;
    }
  chosen_.emplace_back(panel, b);
}

std::string colour_map_name(ColourMap m) { return m == ColourMap::kHighContrast ? "high contrast" : "viridis"; }

Rgb colour_of(ColourMap m, double t) {
  return m == ColourMap::kHighContrast ? interpolate(kHighContrast, t) : interpolate(kViridis, t);
}

double luminance(const Rgb& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

}  // namespace sb
