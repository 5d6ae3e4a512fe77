#include "widgets/rmse_section.hpp"

#include <imgui.h>

#include <algorithm>
#include <cfloat>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <thread>

#include "widgets/panels.hpp"

namespace sb::ui {

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

void RmseSection::draw(const AppSnapshot& snap, const RmseRowOverride& replaced) const {
  const auto series = job_.result();
  if (series.size() != snap.models.size()) {
    ImGui::TextDisabled(job_.running() ? "computing ..." : "no measured frames to compare");
    return;
  }
  const float width = ImGui::GetContentRegionAvail().x;
  for (std::size_t m = 0; m < series.size(); ++m) {
    const bool swapped = static_cast<int>(m) == replaced.slot;
    const std::vector<double>& row = swapped ? replaced.series : series[m];
    // Frames where nothing measured moves do not count (core/calibration/metrics.hpp): drawn as 0.
    std::vector<float> v(row.size());
    double sum = 0;
    int n = 0;
    for (std::size_t k = 0; k < v.size(); ++k) {
      const bool counts = std::isfinite(row[k]);
      v[k] = counts ? static_cast<float>(row[k]) : 0.0f;
      if (counts) sum += row[k], ++n;
    }
    // The answer's id is long: its mean first, so a narrow column cuts the name, not the number.
    char overlay[160];
    if (swapped)
      std::snprintf(overlay, sizeof overlay, "mean %.2f px  %s", n ? sum / n : 0.0, replaced.title.c_str());
    else
      std::snprintf(overlay, sizeof overlay, "%s  mean %.2f px", display_name(snap.models[m].id).c_str(),
                    n ? sum / n : 0.0);
    const ImVec2 p0 = ImGui::GetCursorScreenPos();
    const float h = 34.0f;
    ImGui::PlotLines(("##rmse" + std::to_string(m)).c_str(), v.data(), static_cast<int>(v.size()), 0, overlay, 0.0f,
                     FLT_MAX, ImVec2(width, h));
    if (!v.empty() && snap.step >= 0) {  // the current frame
      const float x = p0.x + width * (static_cast<float>(std::min<std::size_t>(snap.step, v.size() - 1)) + 0.5f) /
                                 static_cast<float>(v.size());
      ImGui::GetWindowDrawList()->AddLine(ImVec2(x, p0.y), ImVec2(x, p0.y + h), IM_COL32(255, 200, 80, 255), 1.5f);
    }
  }
}

}  // namespace sb::ui
