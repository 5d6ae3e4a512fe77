#include "widgets/field_panel.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "widgets/keys.hpp"
#include "widgets/panels.hpp"

namespace sb::ui {

namespace {
constexpr ImU32 kRestColour = IM_COL32(30, 30, 30, 200);
constexpr ImU32 kContactColour = IM_COL32(230, 40, 40, 255);
constexpr ImU32 kFrameColour = IM_COL32(90, 90, 100, 255);
constexpr ImU32 kGelColour = IM_COL32(196, 188, 170, 255);
// The outline under each arrow over a real frame (core/workbench/frame_backdrop: arrow_outline), its alpha and the
// width it adds to the arrow: a dark one nearly opaque; a light one (under a dark arrow on a dimmed frame) thinner
// and half-transparent, so the arrow's own colour still reads.
constexpr float kDarkOutlineAlpha = 0.9f, kDarkOutlineWidth = 2.5f;
constexpr float kLightOutlineAlpha = 0.5f, kLightOutlineWidth = 1.5f;
// Below this magnitude (image px) an arrow is drawn as a dot only.
constexpr double kMinArrowPx = 0.02;

void draw_arrow(ImDrawList* dl, ImVec2 a, ImVec2 b, ImU32 col, float thickness) {
  const float dx = b.x - a.x, dy = b.y - a.y;
  const float len = std::sqrt(dx * dx + dy * dy);
  dl->AddLine(a, b, col, thickness);
  if (len < 3.0f) return;
  const float head = std::min(7.0f, 0.4f * len);
  const float ux = dx / len, uy = dy / len;
  const ImVec2 left(b.x - head * (ux * 0.87f - uy * 0.5f), b.y - head * (uy * 0.87f + ux * 0.5f));
  const ImVec2 right(b.x - head * (ux * 0.87f + uy * 0.5f), b.y - head * (uy * 0.87f - ux * 0.5f));
  dl->AddTriangleFilled(b, left, right, col);
}

}  // namespace

ImU32 to_u32(const Rgb& c, float alpha) {
  return ImGui::ColorConvertFloat4ToU32(ImVec4(float(c.r), float(c.g), float(c.b), alpha));
}

ImU32 colour_map(ColourMap map, float t) { return to_u32(colour_of(map, t), 1.0f); }

namespace {
// A text box with a translucent dark background; `anchor_bottom`: `at` is its bottom-left corner.
void label_box(ImDrawList* dl, ImVec2 at, const std::string& text, ImU32 colour, ImU32 background, bool anchor_bottom) {
  const ImVec2 ts = ImGui::CalcTextSize(text.c_str());
  const ImVec2 c(at.x, anchor_bottom ? at.y - ts.y : at.y);
  dl->AddRectFilled(ImVec2(c.x - 2, c.y - 1), ImVec2(c.x + ts.x + 2, c.y + ts.y + 1), background, 2.0f);
  dl->AddText(c, colour, text.c_str());
}

// The labels over a panel's image: its largest displacement (or that it is off the scale), the metrics against
// the measurement, and the note shown in place of a missing field.
void draw_panel_labels(ImDrawList* dl, const FieldPanelInput& in, const FieldScale& scale, ImVec2 p0, ImVec2 p1,
                       bool any_cut) {
  const bool have_field = in.disp_px != nullptr && !in.disp_px->empty();
  if (have_field) {
    // The panel's own largest displacement, bottom left: the shared arrow scale can make a small field
    // look empty, and a field far above the colour scale is said so in words.
    double max_px = 0;
    for (const Vec2& d : *in.disp_px)
      if (std::isfinite(d.x()) && std::isfinite(d.y())) max_px = std::max(max_px, d.norm());
    const std::string off = off_scale_note(max_px, scale.colour_max_px, any_cut);
    char buf[48];
    std::snprintf(buf, sizeof buf, "max %.2f px", max_px);
    label_box(dl, ImVec2(p0.x + 3, p1.y - 3), off.empty() ? std::string(buf) : off,
              off.empty() ? IM_COL32(255, 255, 255, 255) : IM_COL32(255, 190, 90, 255),
              off.empty() ? IM_COL32(0, 0, 0, 150) : IM_COL32(0, 0, 0, 190), true);
  }
  if (in.metrics) {  // against the measurement, top right of the image (the title row keeps its width)
    char buf[96];
    std::snprintf(buf, sizeof buf, "RMSE %.2f px CS %.2f", in.metrics->rmse_px, in.metrics->cs);
    const ImVec2 ts = ImGui::CalcTextSize(buf);
    label_box(dl, ImVec2(p1.x - ts.x - 3, p0.y + 3), buf, IM_COL32(255, 220, 120, 255), IM_COL32(0, 0, 0, 150), false);
  }
  if (!have_field && !in.note.empty()) {
    const ImVec2 ts = ImGui::CalcTextSize(in.note.c_str());
    const ImVec2 c((p0.x + p1.x - ts.x) / 2, (p0.y + p1.y - ts.y) / 2);
    dl->AddRectFilled(ImVec2(c.x - 4, c.y - 2), ImVec2(c.x + ts.x + 4, c.y + ts.y + 2), IM_COL32(0, 0, 0, 160));
    dl->AddText(c, IM_COL32(255, 255, 255, 255), in.note.c_str());
  }
}
}  // namespace

FieldPanelResult draw_field_panel(const FieldPanelInput& in, const FieldScale& scale, float width, bool interactive) {
  FieldPanelResult result;
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const ImVec2 top = ImGui::GetCursorScreenPos();
  const float line = ImGui::GetTextLineHeightWithSpacing();
  // Title row: the name, and at its right end the button that enlarges the panel (or brings it back).
  // A narrow panel keeps its title whole and shortens the button to "+" (its tooltip says what it does).
  const float pad = 2 * ImGui::GetStyle().FramePadding.x;
  const bool title_fits = ImGui::CalcTextSize(in.title.c_str()).x + ImGui::CalcTextSize("enlarge").x + pad + 4 <= width;
  const char* button = in.enlarged ? "back" : (title_fits ? "enlarge" : "+");
  const float button_w = ImGui::CalcTextSize(button).x + pad;
  // Over a recorded frame, a second button: how the frame sits under this panel's arrows (cycles).
  const char* frame_button = in.real_frame ? "frame" : nullptr;
  const float frame_w = frame_button != nullptr ? ImGui::CalcTextSize(frame_button).x + pad + 4 : 0.0f;
  ImGui::TextUnformatted(elide(in.title, width - button_w - frame_w - 4).c_str());
  if (frame_button != nullptr) {
    ImGui::SetCursorScreenPos(ImVec2(top.x + width - button_w - frame_w, top.y));
    if (ImGui::SmallButton(frame_button)) result.cycle_backdrop = true;
    if (interactive && ImGui::IsItemHovered())
      ImGui::SetTooltip("under the arrows: %s (click: %s)", backdrop_name(in.backdrop).c_str(),
                        backdrop_name(next_backdrop(in.backdrop)).c_str());
  }
  ImGui::SetCursorScreenPos(ImVec2(top.x + width - button_w, top.y));
  if (ImGui::SmallButton(button)) result.toggle_enlarge = true;
  if (interactive && ImGui::IsItemHovered())
    ImGui::SetTooltip(in.enlarged ? "back to all panels (or double-click the field)"
                                  : "enlarge to the whole field area (or double-click the field)");
  const float zoom = width / static_cast<float>(in.image_width_px);
  const float height = in.image_height_px * zoom;
  const ImVec2 p0(top.x, top.y + line);
  const ImVec2 p1(p0.x + width, p0.y + height);
  if (in.background != nullptr) {
    // A recorded frame dimmed (by default) so that the arrows stand out of its white pins.
    const int level = dimmed_channel(255, backdrop_brightness(in.backdrop, in.real_frame));
    dl->AddImage(in.background, p0, p1, ImVec2(0, 0), ImVec2(1, 1), IM_COL32(level, level, level, 255));
  } else
    dl->AddRectFilled(p0, p1, kGelColour);
  dl->AddRect(p0, p1, kFrameColour);
  dl->PushClipRect(p0, p1, true);  // nothing drawn for this field leaves its panel

  const bool hovered = interactive && ImGui::IsWindowHovered() && ImGui::IsMouseHoveringRect(p0, p1);
  if (hovered && mouse_double_clicked()) result.toggle_enlarge = true;
  if (hovered && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) result.clicked = true;
  const ImVec2 mouse = ImGui::GetIO().MousePos;
  // A marker answers the mouse within about half the default marker pitch (33 image px).
  float best_d2 = std::pow(std::max(8.0f, 16.0f * zoom), 2.0f);

  const auto to_screen = [&](const Vec2& uv) {
    return ImVec2(p0.x + float(uv.x()) * zoom, p0.y + float(uv.y()) * zoom);
  };
  const bool have_field = in.disp_px != nullptr && !in.disp_px->empty();
  const float dot = std::max(1.5f, 2.2f * zoom);
  bool any_cut = false;
  if (in.rest_px != nullptr) {
    for (std::size_t m = 0; m < in.rest_px->size(); ++m) {
      const ImVec2 r = to_screen((*in.rest_px)[m]);
      if (hovered) {
        const float d2 = (r.x - mouse.x) * (r.x - mouse.x) + (r.y - mouse.y) * (r.y - mouse.y);
        if (d2 < best_d2) best_d2 = d2, result.hovered_marker = static_cast<int>(m);
      }
      const bool contact = in.in_contact != nullptr && m < in.in_contact->size() && (*in.in_contact)[m] != 0;
      dl->AddCircleFilled(r, dot, contact ? kContactColour : kRestColour);
      if (static_cast<int>(m) == in.highlight_marker) {
        dl->AddCircle(r, dot + 5, IM_COL32(0, 0, 0, 255), 0, 3.0f);
        dl->AddCircle(r, dot + 5, IM_COL32(255, 255, 255, 255), 0, 1.5f);
      }
      if (!have_field || m >= in.disp_px->size()) continue;
      const Vec2 d = (*in.disp_px)[m];
      if (!std::isfinite(d.x()) || !std::isfinite(d.y())) continue;  // a marker the tracker lost
      const double mag = d.norm();
      if (mag < kMinArrowPx) continue;
      const Rgb rgb = colour_of(scale.map, mag / scale.colour_max_px);
      const ImU32 col = to_u32(rgb, 1.0f);
      const std::optional<Rgb> outline = arrow_outline(in.backdrop, in.real_frame, rgb);
      bool cut = false;
      const Vec2 a = drawn_arrow(d, scale.arrow_gain, scale.max_arrow_px, &cut) * zoom;
      const ImVec2 tip(r.x + float(a.x()), r.y + float(a.y()));
      const float thickness = std::max(1.5f, 0.9f * zoom);
      if (outline) {
        const bool light = luminance(*outline) > 0.5;
        draw_arrow(dl, r, tip, to_u32(*outline, light ? kLightOutlineAlpha : kDarkOutlineAlpha),
                   thickness + (light ? kLightOutlineWidth : kDarkOutlineWidth));
      }
      draw_arrow(dl, r, tip, col, thickness);
      if (cut) {  // a second head behind the first: longer than drawn
        any_cut = true;
        const float back = std::min(7.0f, 0.4f * float(a.norm()));
        const float len = float(a.norm());
        draw_arrow(dl, r, ImVec2(tip.x - float(a.x()) / len * back, tip.y - float(a.y()) / len * back), col, thickness);
      }
    }
  }
  draw_panel_labels(dl, in, scale, p0, p1, any_cut);
  dl->PopClipRect();
  ImGui::SetCursorScreenPos(ImVec2(top.x, p1.y + 4));
  ImGui::Dummy(ImVec2(width, 0));
  result.height = line + height + 4;
  return result;
}

// What each mark on a panel is, in one line under the scales.
static void draw_marks_legend(ImVec2 at, ImU32 text) {
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const float cy = at.y + ImGui::GetTextLineHeight() / 2;
  float x = at.x;
  const auto label = [&](const char* t) {
    dl->AddText(ImVec2(x, at.y), text, t);
    x += ImGui::CalcTextSize(t).x + 18;
  };
  dl->AddCircleFilled(ImVec2(x + 4, cy), 3.0f, kRestColour);
  dl->AddCircle(ImVec2(x + 4, cy), 3.5f, IM_COL32(200, 200, 200, 255));
  x += 12;
  label("marker");
  dl->AddCircleFilled(ImVec2(x + 4, cy), 3.5f, kContactColour);
  x += 12;
  label("marker in the model's contact");
  draw_arrow(dl, ImVec2(x, cy), ImVec2(x + 18, cy), text, 1.5f);
  draw_arrow(dl, ImVec2(x, cy), ImVec2(x + 13, cy), text, 1.5f);
  x += 24;
  label("double head: longer than drawn (cut)");
  label("RMSE / CS: against Measured at this frame");
}

float draw_field_legend(const FieldScale& scale, float image_zoom, float width) {
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const ImVec2 top = ImGui::GetCursorScreenPos();
  const float bar_h = 12.0f;
  const float label_w = 60.0f;
  // Colour bar: 0 .. colour_max_px.
  const float bar_w = std::max(60.0f, 0.45f * width - label_w);
  constexpr int kSegments = 48;
  for (int i = 0; i < kSegments; ++i) {
    const float x0 = top.x + label_w + bar_w * i / kSegments, x1 = top.x + label_w + bar_w * (i + 1) / kSegments;
    dl->AddRectFilled(ImVec2(x0, top.y + 3), ImVec2(x1 + 0.5f, top.y + 3 + bar_h),
                      colour_map(scale.map, (i + 0.5f) / kSegments));
  }
  const ImU32 text = ImGui::GetColorU32(ImGuiCol_Text);
  dl->AddText(ImVec2(top.x, top.y), text, "|d|");
  char buf[64];
  dl->AddText(ImVec2(top.x + label_w, top.y + bar_h + 4), text, "0");
  std::snprintf(buf, sizeof buf, "%.3g px", double(scale.colour_max_px));
  dl->AddText(ImVec2(top.x + label_w + bar_w - ImGui::CalcTextSize(buf).x, top.y + bar_h + 4), text, buf);

  // Arrow scale bar: the drawn length of a nice round displacement.
  const float x_bar = top.x + label_w + bar_w + 30.0f;
  const float avail = top.x + width - x_bar - 90.0f;
  const double px_per_disp = double(scale.arrow_gain) * image_zoom;
  // A round displacement near the top of the colour map, shortened until it fits.
  double disp = nice_floor(std::max(1e-3, double(scale.colour_max_px)));
  while (disp * px_per_disp > avail && disp > 1e-3) disp = nice_floor(disp * 0.99);
  const float len = float(disp * px_per_disp);
  const float y = top.y + 3 + bar_h / 2;
  dl->AddLine(ImVec2(x_bar, y), ImVec2(x_bar + len, y), text, 2.0f);
  dl->AddLine(ImVec2(x_bar, y - 5), ImVec2(x_bar, y + 5), text, 2.0f);
  dl->AddLine(ImVec2(x_bar + len, y - 5), ImVec2(x_bar + len, y + 5), text, 2.0f);
  std::snprintf(buf, sizeof buf, "arrow of %g px", disp);
  dl->AddText(ImVec2(x_bar + len + 6, y - ImGui::GetTextLineHeight() / 2), text, buf);
  draw_marks_legend(ImVec2(top.x, top.y + bar_h + 6 + ImGui::GetTextLineHeight() + 2), text);
  const float h = field_legend_height();
  ImGui::Dummy(ImVec2(width, h));
  return h;
}

float field_legend_height() { return 12.0f + 6 + 2 * ImGui::GetTextLineHeight() + 4; }

}  // namespace sb::ui
