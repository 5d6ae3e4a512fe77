#include "widgets/fit_section.hpp"
#include "core/base/format.hpp"

#include <imgui.h>

#include <algorithm>
#include <cstdio>

#include "core/workbench/value_check.hpp"
#include "widgets/panels.hpp"
#include "widgets/text_field.hpp"

namespace sb::ui {

void FitSection::draw(const AppSnapshot& snap, AppState& state, const std::string& replayed_dataset) {
  if (dataset_.empty() && !replayed_dataset.empty()) dataset_ = replayed_dataset;
  ImGui::SetNextItemWidth(-70);
  input_text_with_hint("dataset##fit", "e.g. data:twin/twin_sphere35", dataset_);
  if (snap.models.empty()) return;
  draw_settings(snap);
  const FitJobStatus st = job_.status();
  draw_run_row(snap, st);
  if (!st.losses.empty()) draw_loss_plot(st.losses);
  if (st.phase == FitJobStatus::Phase::kFailed) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1, 0.4f, 0.4f, 1));
    ImGui::TextWrapped("%s", st.error.c_str());
    ImGui::PopStyleColor();
  }
  if (st.result && !result_handled_) draw_result(snap, state, st);
}

// The model to fit, joint refinement and the iteration budget.
void FitSection::draw_settings(const AppSnapshot& snap) {
  model_ = std::clamp(model_, 0, static_cast<int>(snap.models.size()) - 1);
  ImGui::SetNextItemWidth(-70);
  if (ImGui::BeginCombo("model##fit", display_name(snap.models[model_].id).c_str())) {
    for (int m = 0; m < static_cast<int>(snap.models.size()); ++m)
      if (ImGui::Selectable(display_name(snap.models[m].id).c_str(), m == model_)) model_ = m;
    ImGui::EndCombo();
  }
  ImGui::Checkbox("joint refinement", &joint_);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip(
        "on (the default): the paper's stages, then every parameter jointly\noff: the paper's stages only");
  ImGui::SetNextItemWidth(-70);
  ImGui::SliderInt("iterations##fit", &iterations_, 1, 100);
}

// A progress bar and Cancel while the fit runs, else the Run button.
void FitSection::draw_run_row(const AppSnapshot& snap, const FitJobStatus& st) {
  if (st.running()) {
    const float frac = std::min(1.0f, static_cast<float>(st.iteration) / static_cast<float>(std::max(1, iterations_)));
    char label[96];
    std::snprintf(label, sizeof label, "%s  %s  iter %d",
                  st.phase == FitJobStatus::Phase::kLoading ? "loading" : "fitting", st.stage.c_str(), st.iteration);
    ImGui::ProgressBar(frac, ImVec2(-70, 0), label);
    ImGui::SameLine();
    if (ImGui::SmallButton("Cancel##fit")) job_.cancel();
  } else if (ImGui::Button("Run fit (calibration split)")) {
    start(snap);
  }
}

void FitSection::start(const AppSnapshot& snap) {
  FitJobRequest req;
  req.dataset_dir = dataset_;
  req.data_root = data_root_;
  req.model_id = snap.models[model_].id;
  req.start = snap.models[model_].params;
  req.joint = joint_;
  req.max_iterations = iterations_;
  model_id_ = req.model_id;
  start_params_ = req.start;  // the table's "start" column: what the fit started from, not the live sliders
  result_handled_ = false;
  job_.start(std::move(req));
}

// The parameters the fit changed (start and fitted value), then Apply or Discard.
void FitSection::draw_result(const AppSnapshot& snap, AppState& state, const FitJobStatus& st) {
  const bool cancelled = st.phase == FitJobStatus::Phase::kCancelled;
  // Wrapped: the cancelled line is wider than the left column at its default width.
  ImGui::TextWrapped("%s: calibration RMSE %.3f -> %.3f px", cancelled ? "cancelled (completed stages)" : "done",
                     st.calibration_rmse_before_px, st.calibration_rmse_after_px);
  const ParamSet& after = st.result->params;
  std::size_t model = snap.models.size();
  for (std::size_t m = 0; m < snap.models.size(); ++m)
    if (snap.models[m].id == model_id_) model = m;
  if (model == snap.models.size()) return;
  const ParamSet& before = start_params_;
  if (ImGui::BeginTable("##fitresult", 3, ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingStretchProp)) {
    ImGui::TableSetupColumn("parameter");
    ImGui::TableSetupColumn("start");
    ImGui::TableSetupColumn("fitted");
    ImGui::TableHeadersRow();
    for (std::size_t i = 0; i < after.size() && i < before.size(); ++i) {
      if (after[i] == before[i]) continue;
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(after.specs()[i].name.c_str());
      ImGui::TableNextColumn();
      ImGui::Text("%.4g", before[i]);
      ImGui::TableNextColumn();
      ImGui::Text("%.4g", after[i]);
      // A fitted value at its bound is where the search was stopped by the range, not a minimum it found.
      if (at_bound(after.specs()[i], after[i])) at_bound_mark(after.specs()[i]);
    }
    ImGui::EndTable();
  }
  if (ImGui::Button("Apply##fit")) {
    state.request_params(model, after);  // applied at the sync point; the replay re-runs
    result_handled_ = true;
  }
  ImGui::SameLine();
  if (ImGui::Button("Discard##fit")) result_handled_ = true;
}

// The fit's cost per iteration, each stage relative to its own start (stages fit their own parameters on their own
// residuals: their costs are not one curve), stage runs side by side with their names and a separator between.
void FitSection::draw_loss_plot(const std::vector<StageLosses>& stages) {
  std::vector<std::vector<float>> rel;
  std::size_t points = 0;
  float lo = 1.0f;
  for (const StageLosses& st : stages) {
    rel.push_back(relative_to_stage_start(st));
    points += rel.back().size();
    for (float v : rel.back()) lo = std::min(lo, v);
  }
  if (points == 0) return;
  ImGui::TextDisabled("cost per iteration, each stage relative to its start");
  const std::string bottom = format_number(lo, "%.2g");
  const float axis_w = std::max(ImGui::CalcTextSize("1").x, ImGui::CalcTextSize(bottom.c_str()).x) + 6;
  const float h = 60.0f, label_h = ImGui::GetTextLineHeight();
  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  const ImVec2 a(p0.x + axis_w, p0.y + label_h), b(p0.x + ImGui::GetContentRegionAvail().x, p0.y + label_h + h);
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const ImU32 text = ImGui::GetColorU32(ImGuiCol_TextDisabled), line = ImGui::GetColorU32(ImGuiCol_PlotLines);
  dl->AddRect(a, b, ImGui::GetColorU32(ImGuiCol_FrameBg));
  dl->AddText(ImVec2(p0.x, a.y), text, "1");
  dl->AddText(ImVec2(p0.x, b.y - label_h), text, bottom.c_str());
  const float dx = (b.x - a.x) / static_cast<float>(std::max<std::size_t>(1, points - 1));
  const float span = std::max(1.0f - lo, 1e-6f);
  auto y_of = [&](float v) { return b.y - (v - lo) / span * (b.y - a.y); };
  std::size_t first = 0;
  for (std::size_t s = 0; s < rel.size(); ++s) {
    const float x0 = a.x + dx * static_cast<float>(first);
    if (s > 0) dl->AddLine(ImVec2(x0, a.y), ImVec2(x0, b.y), text);
    dl->PushClipRect(ImVec2(x0, p0.y), ImVec2(b.x, b.y), true);
    dl->AddText(ImVec2(x0 + 2, p0.y), text, stages[s].stage.c_str());
    dl->PopClipRect();
    for (std::size_t i = 1; i < rel[s].size(); ++i)
      dl->AddLine(ImVec2(x0 + dx * static_cast<float>(i - 1), y_of(rel[s][i - 1])),
                  ImVec2(x0 + dx * static_cast<float>(i), y_of(rel[s][i])), line, 1.5f);
    first += rel[s].size();
  }
  ImGui::InvisibleButton("##fitloss", ImVec2(b.x - p0.x, b.y - p0.y));
  if (ImGui::IsItemHovered()) draw_loss_tooltip(stages);
  char right[32];
  std::snprintf(right, sizeof right, "%zu", points - 1);
  ImGui::SetCursorScreenPos(ImVec2(a.x, b.y + 2));
  ImGui::TextDisabled("0");
  const float label_w = ImGui::CalcTextSize("iteration").x;
  ImGui::SameLine((a.x + b.x - label_w) / 2 - ImGui::GetWindowPos().x, 0);
  ImGui::TextDisabled("iteration");
  ImGui::SameLine(b.x - ImGui::CalcTextSize(right).x - ImGui::GetWindowPos().x, 0);
  ImGui::TextDisabled("%s", right);
}

// Each stage's cost at its start and end, in the fit's own units.
void FitSection::draw_loss_tooltip(const std::vector<StageLosses>& stages) {
  ImGui::BeginTooltip();
  for (const StageLosses& st : stages)
    if (!st.costs.empty())
      ImGui::Text("%s: cost %s -> %s (%zu iterations)", st.stage.c_str(),
                  format_number(st.costs.front(), "%.4g").c_str(), format_number(st.costs.back(), "%.4g").c_str(),
                  st.costs.size());
  ImGui::EndTooltip();
}

}  // namespace sb::ui
