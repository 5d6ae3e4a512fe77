#pragma once
// The workbench's two columns: how wide the left (controls) column is, from the window's width and the width the
// user dragged the divider to. GL-free, tested in tests/test_column_layout.cpp.

namespace sb {

struct ColumnLimits {
  float min_left_px = 300;   // below this the sliders' labels are cut
  float min_right_px = 480;  // the 3D view and one row of field panels stay usable
};

// The left column's width in pixels: `dragged_px` (<= 0: never dragged, a quarter of the window, at most 400 px)
// held to [min_left_px, window_px - min_right_px]; a window narrower than both minima gets min_left_px.
float left_column_px(float window_px, float dragged_px, const ColumnLimits& limits = {});

}  // namespace sb
