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
  ImGui::Text("%s: calibration RMSE %.3f -> %.3f px", cancelled ? "cancelled (completed stages)" : "done",
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

// The fit's loss per iteration with its axes: cost (least squares, log of the largest and smallest) against iteration.
void FitSection::draw_loss_plot(const std::vector<float>& losses) {
  const auto [lo, hi] = std::minmax_element(losses.begin(), losses.end());
  const std::string top = format_number(*hi, "%.3g"), bottom = format_number(*lo, "%.3g");
  const float axis_w = std::max(ImGui::CalcTextSize(top.c_str()).x, ImGui::CalcTextSize(bottom.c_str()).x) + 6;
  const float h = 60.0f;
  ImGui::TextDisabled("least-squares cost per iteration (all stages)");
  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const ImU32 text = ImGui::GetColorU32(ImGuiCol_TextDisabled);
  dl->AddText(ImVec2(p0.x, p0.y), text, top.c_str());
  dl->AddText(ImVec2(p0.x, p0.y + h - ImGui::GetTextLineHeight()), text, bottom.c_str());
  ImGui::SetCursorScreenPos(ImVec2(p0.x + axis_w, p0.y));
  ImGui::PlotLines("##fitloss", losses.data(), static_cast<int>(losses.size()), 0, nullptr, *lo, *hi,
                   ImVec2(ImGui::GetContentRegionAvail().x, h));
  char right[32];
  std::snprintf(right, sizeof right, "%zu", losses.size() - 1);
  const float x1 = ImGui::GetItemRectMax().x;
  ImGui::SetCursorScreenPos(ImVec2(p0.x + axis_w, p0.y + h + 2));
  ImGui::TextDisabled("0");
  ImGui::SameLine(0, 0);
  const float label_w = ImGui::CalcTextSize("iteration").x;
  ImGui::SetCursorScreenPos(ImVec2((p0.x + axis_w + x1 - label_w) / 2, p0.y + h + 2));
  ImGui::TextDisabled("iteration");
  ImGui::SameLine(0, 0);
  ImGui::SetCursorScreenPos(ImVec2(x1 - ImGui::CalcTextSize(right).x, p0.y + h + 2));
  ImGui::TextDisabled("%s", right);
}

}  // namespace sb::ui
