#include "widgets/rmse_section.hpp"

#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>

#include "core/base/atomic_write.hpp"
#include "core/workbench/timeline_plot.hpp"
#include "widgets/panels.hpp"

namespace sb::ui {

namespace {

// "name  mean" in at most `max_w` pixels: a long name (the loop's answer, a form with its effects) is cut with "..".
std::string legend_label(const std::string& name, double mean_px, float max_w) {
  char mean[32];
  std::snprintf(mean, sizeof mean, "  %.2f", mean_px);
  return elide(name, max_w - ImGui::CalcTextSize(mean).x) + mean;
}

// The models' colours, in slot order (the legend says which is which).
constexpr ImU32 kModelColours[] = {IM_COL32(90, 170, 255, 255),  IM_COL32(255, 140, 60, 255),
                                   IM_COL32(110, 210, 110, 255), IM_COL32(235, 90, 110, 255),
                                   IM_COL32(190, 140, 255, 255), IM_COL32(230, 210, 80, 255)};
constexpr ImU32 kAxisColour = IM_COL32(150, 150, 160, 255);
constexpr ImU32 kLabelColour = IM_COL32(190, 190, 200, 255);
constexpr ImU32 kCursorColour = IM_COL32(255, 200, 80, 255);
// Room for the RMSE axis' labels (left) and the time axis' (below).
constexpr float kLeftMarginPx = 30.0f;
constexpr float kBottomMarginPx = 13.0f;

ImU32 model_colour(std::size_t slot) { return kModelColours[slot % std::size(kModelColours)]; }

void draw_axes(ImDrawList* dl, const TimelinePlot& plot) {
  char buf[32];
  const float bottom = plot.top + plot.height;
  dl->AddLine(ImVec2(plot.left, plot.top), ImVec2(plot.left, bottom), kAxisColour);
  dl->AddLine(ImVec2(plot.left, bottom), ImVec2(plot.left + plot.width, bottom), kAxisColour);
  const float font = ImGui::GetFontSize();
  // A label every two lines at most: dense labels run into each other and into the unit.
  for (const auto& t : plot.rmse_ticks(std::max(1, static_cast<int>(plot.height / (2 * font))))) {
    dl->AddLine(ImVec2(plot.left - 3, t.px), ImVec2(plot.left, t.px), kAxisColour);
    std::snprintf(buf, sizeof buf, "%g", t.value);
    const float w = ImGui::CalcTextSize(buf).x;
    dl->AddText(ImVec2(plot.left - 4 - w, std::clamp(t.px - font / 2, plot.top - 2, bottom - font)), kLabelColour, buf);
  }
  // The unit inside the plot, top left: beside the axis it would run into the top tick's label.
  dl->AddText(ImVec2(plot.left + 3, plot.top - 2), kLabelColour, "px");
  for (const auto& t : plot.time_ticks(std::max(1, static_cast<int>(plot.width / 45)))) {
    dl->AddLine(ImVec2(t.px, bottom), ImVec2(t.px, bottom + 3), kAxisColour);
    std::snprintf(buf, sizeof buf, "%g", t.value);
    dl->AddText(ImVec2(t.px - ImGui::CalcTextSize(buf).x / 2, bottom + 1), kLabelColour, buf);
  }
  const float sw = ImGui::CalcTextSize("s").x;
  dl->AddText(ImVec2(plot.left + plot.width - sw, bottom + 1), kLabelColour, "s");
}

void draw_series(ImDrawList* dl, const TimelinePlot& plot, const std::vector<double>& row, ImU32 colour) {
  // Frames where nothing measured moves do not count (core/calibration/metrics.hpp): a gap in the line.
  std::vector<ImVec2> run;
  const auto flush = [&] {
    if (run.size() == 1) dl->AddCircleFilled(run[0], 1.5f, colour);
    if (run.size() > 1) dl->AddPolyline(run.data(), static_cast<int>(run.size()), colour, ImDrawFlags_None, 1.5f);
    run.clear();
  };
  for (std::size_t k = 0; k < row.size(); ++k) {
    if (!std::isfinite(row[k])) {
      flush();
      continue;
    }
    run.push_back(ImVec2(plot.x_of_step(static_cast<double>(k)), plot.y_of_value(row[k])));
  }
  flush();
}

double mean_of(const std::vector<double>& row) {
  double sum = 0;
  int n = 0;
  for (const double v : row)
    if (std::isfinite(v)) sum += v, ++n;
  return n ? sum / n : 0.0;
}

}  // namespace

void RmseSection::update(const AppSnapshot& snap, const AppState& state, const MeasuredData& measured) {
  if (measured.disp_px.empty() || measured.poses.empty() || state.pending_edits() != 0) return;
  std::vector<std::vector<double>> values;
  for (const auto& m : snap.models) values.push_back(m.params.values());
  if (values.empty() || values == params_) return;
  RmseSeriesRequest req;
  for (const auto& m : snap.models) {
    req.model_ids.push_back(m.id);
    req.params.push_back(m.params);
  }
  req.sensor = state.sensor();
  req.indenter = state.indenter();
  req.path = measured.poses;
  req.dt_s = snap.dt_s;
  req.measured_px = measured.disp_px;
  job_.start(std::move(req));
  params_ = std::move(values);
}

void RmseSection::wait() const {
  while (job_.running()) std::this_thread::sleep_for(std::chrono::milliseconds(2));
}

void RmseSection::draw(const AppSnapshot& snap, AppState& state, const std::string& csv_path, std::string& message,
                       const RmseRowOverride& replaced) const {
  const auto series = job_.result();
  if (series.size() != snap.models.size()) {
    ImGui::TextDisabled(job_.running() ? "computing ..." : "no measured frames to compare");
    return;
  }
  std::vector<std::vector<double>> rows(series.begin(), series.end());
  std::vector<std::string> names;
  for (std::size_t m = 0; m < rows.size(); ++m) {
    const bool swapped = static_cast<int>(m) == replaced.slot;
    if (swapped) rows[m] = replaced.series;
    names.push_back(swapped ? replaced.title : display_name(snap.models[m].id));
  }
  std::size_t steps = 1;
  double top = 0;
  for (const auto& r : rows) {
    steps = std::max(steps, r.size());
    for (const double v : r)
      if (std::isfinite(v)) top = std::max(top, v);
  }
  // As tall as the one row per model it replaces, so the sections under it stay where they were.
  const float spacing = ImGui::GetStyle().ItemSpacing.y;
  const float h = static_cast<float>(rows.size()) * (34.0f + spacing) - spacing;
  const float width = ImGui::GetContentRegionAvail().x;
  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  TimelinePlot plot;
  plot.left = p0.x + kLeftMarginPx;
  plot.top = p0.y + 2;
  plot.width = std::max(1.0f, width - kLeftMarginPx - 4);
  plot.height = std::max(1.0f, h - kBottomMarginPx - 2);
  plot.num_steps = static_cast<int>(steps);
  plot.dt_s = snap.dt_s;
  plot.y_max_px = nice_axis_max(top, std::max(1, static_cast<int>(plot.height / (2 * ImGui::GetFontSize()))));

  // Click or drag over the plot (and its time axis) seeks; the corner under the RMSE axis holds the CSV button.
  ImGui::SetCursorScreenPos(ImVec2(plot.left, p0.y));
  ImGui::InvisibleButton("##rmse_timeline", ImVec2(width - kLeftMarginPx, h));
  if (ImGui::IsItemActive()) {
    const int k = plot.step_at(ImGui::GetIO().MousePos.x);
    if (k != snap.step) state.request_seek(k);
  }
  if (ImGui::IsItemHovered()) {
    const int k = plot.step_at(ImGui::GetIO().MousePos.x);
    std::string tip = "step " + std::to_string(k) + "  t = ";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.2f s", k * snap.dt_s);
    tip += buf;
    for (std::size_t m = 0; m < rows.size(); ++m) {
      if (k < static_cast<int>(rows[m].size()) && std::isfinite(rows[m][k]))
        std::snprintf(buf, sizeof buf, "%.2f px", rows[m][k]);
      else
        std::snprintf(buf, sizeof buf, "-");
      tip += "\n" + names[m] + ": " + buf;
    }
    ImGui::SetTooltip("%s\n(click or drag to seek)", tip.c_str());
  }
  const ImVec2 after = ImGui::GetCursorScreenPos();

  ImDrawList* dl = ImGui::GetWindowDrawList();
  draw_axes(dl, plot);
  for (std::size_t m = 0; m < rows.size(); ++m) draw_series(dl, plot, rows[m], model_colour(m));
  if (snap.step >= 0) {  // the current frame
    const float x = plot.x_of_step(std::min<double>(snap.step, static_cast<double>(steps - 1)));
    dl->AddLine(ImVec2(x, plot.top), ImVec2(x, plot.top + plot.height), kCursorColour, 1.5f);
  }
  // The legend, top right: each model's name and mean in its colour.
  float y = plot.top;
  for (std::size_t m = 0; m < rows.size() && y + ImGui::GetFontSize() <= plot.top + plot.height + 1; ++m) {
    const std::string text = legend_label(names[m], mean_of(rows[m]), plot.width - 8);
    const char* label = text.c_str();
    const float w = ImGui::CalcTextSize(label).x;
    // A dark box under each name, so the lines it crosses do not hide it.
    dl->AddRectFilled(ImVec2(plot.left + plot.width - w - 4, y),
                      ImVec2(plot.left + plot.width, y + ImGui::GetFontSize()), IM_COL32(20, 20, 25, 190));
    dl->AddText(ImVec2(plot.left + plot.width - w - 2, y), model_colour(m), label);
    y += ImGui::GetFontSize();
  }

  ImGui::SetCursorScreenPos(ImVec2(p0.x, p0.y + h - ImGui::GetFontSize()));
  ImGui::PushStyleVar(ImGuiStyleVar_FramePadding, ImVec2(1, 0));
  const bool csv = ImGui::SmallButton("CSV##rmse");
  ImGui::PopStyleVar();
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("writes %s (step, time_s, one column per model)", csv_path.c_str());
  if (csv) {
    try {
      const auto dir = std::filesystem::path(csv_path).parent_path();
      if (!dir.empty()) std::filesystem::create_directories(dir);
      write_file_atomic(csv_path, timeline_csv(names, rows, snap.dt_s));
      message = "wrote the RMSE timeline to " + csv_path;
    } catch (const std::exception& e) {
      message = std::string("error: RMSE timeline CSV: ") + e.what();
    }
  }
  ImGui::SetCursorScreenPos(after);  // under the plot, where the rows it replaces ended
}

}  // namespace sb::ui
