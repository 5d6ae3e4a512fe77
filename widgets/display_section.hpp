#pragma once
// The Display section: the shared arrow gain and colour scale (auto, held at the largest, or fixed), the
// model the 3D view's markers are coloured by, the camera presets and the screenshot row. It owns the field
// scale every panel draws with.
#include <string>
#include <vector>

#include "core/workbench/colour_scale.hpp"

#include "core/workbench/app_state.hpp"
#include "widgets/field_panel.hpp"
#include "widgets/viewport.hpp"
#include "widgets/workbench_request.hpp"

namespace sb::ui {

class DisplaySection {
 public:
  // A new session: the marker pitch (smallest distance between two rest markers, for the automatic arrow
  // scale), the sample's largest measured displacement (the dataset's own colour scale) and the dataset's
  // name ("" for a scene: the colours held for a dataset stay with it, core/workbench/colour_scale).
  void start_session(const std::vector<Vec2>& rest_px, const std::vector<std::vector<Vec2>>& measured_px,
                     const std::string& dataset);
  // The automatic scale for this frame: `measured` is the measurement at the step, null without one.
  void auto_scale(const std::vector<Vec2>* measured, const AppSnapshot& snap);
  void draw(const AppSnapshot& snap, Viewport3D& viewport, const std::vector<ScreenRegion>& regions,
            WorkbenchRequest& req);

  FieldScale& scale() { return scale_; }
  const FieldScale& scale() const { return scale_; }
  bool& auto_scale_enabled() { return auto_scale_; }
  // Keyboard: longer or shorter arrows (by 1.25) fix the scale.
  void lengthen_arrows(bool longer) {
    auto_scale_ = false;
    if (longer)
      scale_.arrow_gain *= 1.25f;
    else
      scale_.arrow_gain /= 1.25f;
  }
  // The model whose |d| colours the 3D view's markers (a panel click or the combo chooses it).
  int marker_model() const { return marker_model_; }
  void set_marker_model(int model) { marker_model_ = model; }
  void next_marker_model(int models) { marker_model_ = (marker_model_ + 1) % std::max<int>(1, models); }

 private:
  void draw_scale_controls();
  void draw_colour_map_combo();
  void draw_marker_model_combo(const AppSnapshot& snap);
  void draw_screenshot_row(const std::vector<ScreenRegion>& regions, WorkbenchRequest& req);

  void take(const ScaleSetting& s);

  FieldScale scale_;
  bool auto_scale_ = true;
  ColourScaleKeeper keeper_;  // the dataset's own scale, and colours held per dataset
  double marker_pitch_px_ = 33.0;
  int marker_model_ = 0;
  int screenshot_region_ = 0;  // 0: window, i: regions[i - 1]
};

}  // namespace sb::ui
