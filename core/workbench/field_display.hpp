#pragma once
// How a field panel shows a field far off the shared scale, without a window (widgets/field_panel draws
// it): arrows cut to a longest length, and the words the panel shows when the field is far above the
// top of the colour map.
#include <string>

#include "core/geometry/pose.hpp"

namespace sb {

// A field this many times the top of the colour map is called out in words on its panel.
inline constexpr double kOffScaleFactor = 5.0;

// "field up to 44.2 px,\n44x the colour scale:\narrows clipped" (three short lines: a panel is narrow),
// empty when max_px is within kOffScaleFactor of colour_max_px. `clipped`: some arrow was cut.
std::string off_scale_note(double max_px, double colour_max_px, bool clipped);
// The drawn arrow of displacement `d` (image px) at `gain`, cut to `max_len` (0: no cut); `*cut` says
// whether it was.
Vec2 drawn_arrow(const Vec2& d, double gain, double max_len, bool* cut);

}  // namespace sb
