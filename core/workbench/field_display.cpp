#include "core/workbench/field_display.hpp"

#include <cstdio>

namespace sb {

std::string off_scale_note(double max_px, double colour_max_px, bool clipped) {
  if (!(colour_max_px > 0) || !(max_px > kOffScaleFactor * colour_max_px)) return {};
  char buf[128];
  std::snprintf(buf, sizeof buf, "field up to %.3g px,\n%.0fx the colour scale%s", max_px, max_px / colour_max_px,
                clipped ? ":\narrows clipped" : "");
  return buf;
}

Vec2 drawn_arrow(const Vec2& d, double gain, double max_len, bool* cut) {
  Vec2 a = d * gain;
  const double len = a.norm();
  *cut = max_len > 0 && len > max_len;
  if (*cut) a *= max_len / len;
  return a;
}

}  // namespace sb
