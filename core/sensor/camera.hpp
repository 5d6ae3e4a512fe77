#pragma once
// The orthographic GelSight camera of tsd/1 (FORMAT.md): a gel-surface point (x, y) in E is seen at
//   u = cu + x / s,  v = cv + y / s,  s = mm_per_px * 1e-3 metres per pixel, (cu, cv) = principal_px.
#include "core/geometry/pose.hpp"

namespace sb {

struct Camera {
  double mm_per_px = 0.0634;
  Vec2 principal_px{159.5, 119.5};
  int width_px = 320;
  int height_px = 240;

  double metres_per_px() const { return mm_per_px * 1e-3; }
  double px_per_metre() const { return 1.0 / metres_per_px(); }
  Vec2 px_from_E(const Vec2& p_E_xy) const { return principal_px + p_E_xy / metres_per_px(); }
  Vec2 E_from_px(const Vec2& uv) const { return (uv - principal_px) * metres_per_px(); }
  // Displacements map without the offset.
  Vec2 px_displacement(const Vec2& d_E_xy) const { return d_E_xy / metres_per_px(); }
  Vec2 E_displacement(const Vec2& d_uv) const { return d_uv * metres_per_px(); }
};

}  // namespace sb
