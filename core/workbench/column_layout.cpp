#include "core/workbench/column_layout.hpp"

#include <algorithm>

namespace sb {

float left_column_px(float window_px, float dragged_px, const ColumnLimits& limits) {
  const float wanted = dragged_px > 0 ? dragged_px : std::min(0.25f * window_px, 400.0f);
  const float widest = std::max(limits.min_left_px, window_px - limits.min_right_px);
  return std::clamp(wanted, limits.min_left_px, widest);
}

}  // namespace sb
