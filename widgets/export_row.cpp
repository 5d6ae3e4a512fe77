#include "widgets/export_row.hpp"

#include <imgui.h>

#include <cstdio>
#include <utility>

#include "widgets/text_field.hpp"

namespace sb::ui {

void ExportRow::draw(WorkbenchRequest& req) {
  const FieldExportStatus st = job_.status();
  if (st.running()) {
    char label[96];
    std::snprintf(label, sizeof label, "exporting  %s  %.0f %%", st.stage.c_str(), 100.0 * st.fraction);
    ImGui::ProgressBar(static_cast<float>(st.fraction), ImVec2(-70, 0), label);
    ImGui::SameLine();
    if (ImGui::SmallButton("Cancel##export")) job_.cancel();
    return;
  }
  next_item_leaves_label_room();
  input_text("##exportdir", folder_);
  ImGui::SameLine();
  if (ImGui::SmallButton("Export fields")) req.export_fields = folder_;
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("writes <folder>/<model>/ (tsd/1) for every model");
}

void ExportRow::start(FieldExportRequest request) {
  reported_ = false;
  job_.start(std::move(request));
}

bool ExportRow::take_report(std::string& message) {
  if (reported_) return false;
  const FieldExportStatus st = job_.status();
  using Phase = FieldExportStatus::Phase;
  if (st.phase == Phase::kRunning || st.phase == Phase::kIdle) return false;
  reported_ = true;
  if (st.phase == Phase::kDone)
    message = "exported " + std::to_string(st.written) + " fields (tsd/1) to " + st.dir;
  else if (st.phase == Phase::kCancelled)
    message = "export cancelled; nothing was written to " + st.dir;
  else
    message = "error: export to " + st.dir + ": " + st.error;
  return true;
}

}  // namespace sb::ui
