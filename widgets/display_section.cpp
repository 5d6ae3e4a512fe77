#include "widgets/display_section.hpp"

#include <imgui.h>

#include <algorithm>
#include <cfloat>
#include <cmath>

#include "widgets/panels.hpp"
#include "widgets/text_field.hpp"

namespace sb::ui {

namespace {
// The longest arrow drawn, in marker pitches: one and a half reaches past the next marker without
// crossing the panel (FOTS's 44 px at the default scene's gain would be 70 pitches).
constexpr double kMaxArrowPitches = 1.5;

double largest_finite(const std::vector<Vec2>& d) {
  double m = 0;
  for (const Vec2& v : d)
    if (std::isfinite(v.x()) && std::isfinite(v.y())) m = std::max(m, v.norm());
  return m;
}
}  // namespace

void DisplaySection::start_session(const std::vector<Vec2>& rest, const std::vector<std::vector<Vec2>>& measured_px,
                                   const std::string& dataset) {
  double pitch = 1e9;
  for (std::size_t i = 0; i < rest.size(); ++i)
    for (std::size_t j = i + 1; j < rest.size(); ++j) pitch = std::min(pitch, (rest[i] - rest[j]).norm());
  marker_pitch_px_ = pitch < 1e9 && pitch > 0 ? pitch : 33.0;
  scale_.max_arrow_px = static_cast<float>(kMaxArrowPitches * marker_pitch_px_);
  // The scale starts at once from the dataset's own (its sample's largest measurement), before any frame
  // has a field: a scale from the dataset open before is never carried over (unless held for this one).
  double sample_max_px = 0;
  for (const auto& frame : measured_px)
    for (const Vec2& d : frame)
      if (d.allFinite()) sample_max_px = std::max(sample_max_px, d.norm());
  keeper_.open(dataset, sample_max_px, marker_pitch_px_);
  if (auto_scale_) take(keeper_.current());
}

void DisplaySection::take(const ScaleSetting& s) {
  scale_.arrow_gain = static_cast<float>(s.arrow_gain);
  scale_.colour_max_px = static_cast<float>(s.colour_max_px);
}

void DisplaySection::auto_scale(const std::vector<Vec2>* measured, const AppSnapshot& snap) {
  // The reference field sets the scale: the measurement when there is one, else the median of the
  // models' largest displacements (one model far off should not flatten the others).
  double max_px = 0;
  if (measured != nullptr) {
    max_px = largest_finite(*measured);
  } else {
    std::vector<double> maxes;
    for (const auto& m : snap.models) maxes.push_back(largest_finite(m.out.disp_px));
    if (!maxes.empty()) {
      std::sort(maxes.begin(), maxes.end());
      max_px = maxes[maxes.size() / 2];
    }
  }
  // Arrows follow the frame (the legend's scale bar says how long a pixel is drawn); colours, held, only
  // grow (from a sample's largest measurement on), so a colour keeps its meaning through a drag or a replay
  // (the colour maximum once went 2 -> 40 -> 10 px within one drag). A frame without a field keeps the scale.
  take(keeper_.at_frame(max_px));
}

void DisplaySection::draw(const AppSnapshot& snap, Viewport3D& viewport, const std::vector<ScreenRegion>& regions,
                          WorkbenchRequest& req) {
  draw_scale_controls();
  draw_marker_model_combo(snap);
  if (ImGui::SmallButton("Top")) viewport.set_camera(CameraPreset::kTop);
  ImGui::SameLine();
  if (ImGui::SmallButton("Side")) viewport.set_camera(CameraPreset::kSide);
  ImGui::SameLine();
  if (ImGui::SmallButton("Iso")) viewport.set_camera(CameraPreset::kIso);
  ImGui::SameLine();
  draw_colour_map_combo();
  draw_screenshot_row(regions, req);
}

void DisplaySection::draw_scale_controls() {
  ImGui::Checkbox("auto scale", &auto_scale_);
  ImGui::SameLine();
  bool hold = keeper_.hold();
  if (ImGui::Checkbox("hold colours", &hold)) keeper_.set_hold(hold);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip(
        "on: the colour scale only grows (a dataset sample: from its largest measured |d|), so a\n"
        "colour means the same from frame to frame; the arrows still follow each frame.\n"
        "Held for this dataset only: another dataset opens at its own scale.\n"
        "off: colours follow every frame. Untick auto scale to fix both at the sliders' values.");
  // On the checkboxes' row (and the colour map on the camera buttons'): the rows below keep their places.
  ImGui::SameLine();
  if (ImGui::SmallButton("reset##colour_scale")) {
    auto_scale_ = true;
    take(keeper_.reset());
  }
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip(
        "reset the colour scale: colour max and arrow gain back to this dataset's own\n"
        "(its sample's largest measured |d|)");
  next_item_leaves_label_room();
  if (ImGui::SliderFloat("arrow gain", &scale_.arrow_gain, 0.2f, 200.0f, "%.3gx", ImGuiSliderFlags_Logarithmic))
    auto_scale_ = false;
  next_item_leaves_label_room();
  if (ImGui::SliderFloat("colour max", &scale_.colour_max_px, 0.05f, 50.0f, "%.3g px", ImGuiSliderFlags_Logarithmic))
    auto_scale_ = false;
}

void DisplaySection::draw_colour_map_combo() {
  ImGui::SetNextItemWidth(-FLT_MIN);
  if (ImGui::BeginCombo("##colour_map", colour_map_name(scale_.map).c_str())) {
    for (const ColourMap m : kColourMaps)
      if (ImGui::Selectable(colour_map_name(m).c_str(), m == scale_.map)) scale_.map = m;
    ImGui::EndCombo();
  }
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("colour map of |d| in every panel and the 3D markers");
}

void DisplaySection::draw_marker_model_combo(const AppSnapshot& snap) {
  if (snap.models.empty()) return;
  next_item_leaves_label_room();
  marker_model_ = std::clamp(marker_model_, 0, int(snap.models.size()) - 1);
  if (ImGui::BeginCombo("3D markers", display_name(snap.models[marker_model_].id).c_str())) {
    for (int i = 0; i < int(snap.models.size()); ++i)
      if (ImGui::Selectable(display_name(snap.models[i].id).c_str(), i == marker_model_)) marker_model_ = i;
    ImGui::EndCombo();
  }
}

// Screenshot of the window or of one panel (PNG under screenshots/).
void DisplaySection::draw_screenshot_row(const std::vector<ScreenRegion>& regions, WorkbenchRequest& req) {
  next_item_leaves_label_room();
  const bool region_shown = screenshot_region_ > 0 && screenshot_region_ <= int(regions.size());
  const char* shown = region_shown ? regions[screenshot_region_ - 1].name.c_str() : "whole window";
  if (ImGui::BeginCombo("##shotregion", shown)) {
    if (ImGui::Selectable("whole window", screenshot_region_ == 0)) screenshot_region_ = 0;
    for (int i = 0; i < int(regions.size()); ++i)
      if (ImGui::Selectable(regions[i].name.c_str(), screenshot_region_ == i + 1)) screenshot_region_ = i + 1;
    ImGui::EndCombo();
  }
  ImGui::SameLine();
  if (ImGui::SmallButton("Screenshot")) {
    req.screenshot = true;
    if (screenshot_region_ > 0 && screenshot_region_ <= int(regions.size()))
      req.screenshot_region = regions[screenshot_region_ - 1].name;
  }
}

}  // namespace sb::ui
