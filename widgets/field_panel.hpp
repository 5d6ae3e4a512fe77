#pragma once
// One marker-field panel (HydroShear | FOTS | TacSL | Measured): the sensor image (a real frame, else a
// neutral gel image), the marker grid, displacement arrows on one shared scale coloured by magnitude,
// a colour legend, a pixel scale bar, and when a measurement exists that frame's RMSE and CS.
// Drawn with ImGui draw lists, so the GUI and the headless render draw the same pixels.
#include <imgui.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/geometry/pose.hpp"
#include "core/workbench/colour_scale.hpp"    // nice_floor
#include "core/workbench/field_display.hpp"   // off_scale_note, drawn_arrow
#include "core/workbench/frame_backdrop.hpp"  // FrameBackdrop, ColourMap

namespace sb::ui {

struct FieldScale {
  float arrow_gain = 4.0f;     // drawn arrow length / displacement (both in image pixels)
  float colour_max_px = 2.0f;  // displacement magnitude at the top of the colour map
  // Longest arrow drawn (image pixels; 0: no limit). A longer one is cut to this length and drawn with
  // a double head, so one model far off the shared scale does not bury its panel in lines.
  float max_arrow_px = 0.0f;
  ColourMap map = ColourMap::kViridis;  // shared by every panel and the 3D view
};

struct FieldMetrics {
  double rmse_px = 0;
  double cs = 0;  // cosine similarity of the fields
};

struct FieldPanelInput {
  std::string title;
  const std::vector<Vec2>* rest_px = nullptr;  // marker rest positions (image pixels)
  const std::vector<Vec2>* disp_px = nullptr;  // null or empty: nothing to draw
  const std::vector<std::uint8_t>* in_contact = nullptr;
  ImTextureID background = nullptr;
  bool real_frame = false;                          // `background` is a recorded frame (not the neutral gel)
  FrameBackdrop backdrop = FrameBackdrop::kDimmed;  // how that frame sits under the arrows
  int image_width_px = 320;
  int image_height_px = 240;
  std::optional<FieldMetrics> metrics;
  std::string note;           // shown when there is no field
  int highlight_marker = -1;  // drawn ringed (the marker hovered in any panel)
  bool enlarged = false;      // the enlarge button shows "back" instead
};

struct FieldPanelResult {
  float height = 0;             // the height used
  int hovered_marker = -1;      // the marker under the mouse (nearest within reach), -1: none
  bool toggle_enlarge = false;  // the enlarge / back button was pressed, or the image double-clicked
  bool clicked = false;         // the image was clicked (the workbench shows this model in the 3D view)
  bool cycle_backdrop = false;  // the frame button was pressed: the next FrameBackdrop for this panel
};

// RGBA of a magnitude on colour map `map` (t in [0, 1], clamped; core/workbench/frame_backdrop).
ImU32 colour_map(ColourMap map, float t);
ImU32 to_u32(const Rgb& c, float alpha);

// Draws at the cursor into a box of `width` pixels (title row, then the image). `interactive`: hover and
// the enlarge button answer the mouse.
FieldPanelResult draw_field_panel(const FieldPanelInput& in, const FieldScale& scale, float width,
                                  bool interactive = true);
// The shared legend: colour bar 0..colour_max_px, the arrow scale bar, and a line saying what every mark
// is (a marker, a marker in the model's contact, a cut arrow, the hovered marker). Returns the height used.
float draw_field_legend(const FieldScale& scale, float image_zoom, float width);
float field_legend_height();

}  // namespace sb::ui
