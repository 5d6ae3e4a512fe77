#include "widgets/dialogs.hpp"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "widgets/keys.hpp"

namespace sb::ui {

namespace {
// The next window centred on the main viewport.
void centre_next_window() {
  const ImGuiViewport* vp = ImGui::GetMainViewport();
  ImGui::SetNextWindowPos(ImVec2(vp->Pos.x + vp->Size.x / 2, vp->Pos.y + vp->Size.y / 2), ImGuiCond_Always,
                          ImVec2(0.5f, 0.5f));
}
}  // namespace

void QuestionDialog::ask(std::string id, std::string text, std::vector<std::string> buttons) {
  id_ = std::move(id);
  text_ = std::move(text);
  buttons_ = std::move(buttons);
}

void QuestionDialog::draw(WorkbenchRequest& req) {
  if (id_.empty()) return;
  ImGui::OpenPopup("##question");
  centre_next_window();
  if (ImGui::BeginPopupModal("##question", nullptr, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoTitleBar)) {
    ImGui::TextUnformatted(text_.c_str());
    ImGui::Separator();
    // Enter answers with the first button, the one that keeps the user's work (Restore; Save and close).
    const bool enter = take_enter_press();
    for (std::size_t i = 0; i < buttons_.size(); ++i) {
      if (i > 0) ImGui::SameLine();
      if (ImGui::Button(buttons_[i].c_str(), ImVec2(110, 0)) || (i == 0 && enter)) {
        req.answer = std::make_pair(id_, static_cast<int>(i));
        id_.clear();
        ImGui::CloseCurrentPopup();
      }
    }
    if (!buttons_.empty()) ImGui::TextDisabled("Enter: %s", buttons_[0].c_str());
    ImGui::EndPopup();
  }
}

void LoadingDialog::set(std::string what) {
  if (what_.empty() && !what.empty()) since_ = std::chrono::steady_clock::now();
  what_ = std::move(what);
}

void LoadingDialog::draw() {
  if (what_.empty()) return;
  ImGui::OpenPopup("##loading");
  centre_next_window();
  const ImGuiViewport* vp = ImGui::GetMainViewport();
  ImGui::SetNextWindowSize(ImVec2(std::min(560.0f, vp->Size.x - 40), 0));
  if (ImGui::BeginPopupModal("##loading", nullptr, ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoResize)) {
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - since_).count();
    ImGui::TextWrapped("opening %s ...", what_.c_str());
    char label[32];
    std::snprintf(label, sizeof label, "%.1f s", s);
    // No fraction is known: a bar that sweeps back and forth says the work is alive.
    ImGui::ProgressBar(static_cast<float>(0.5 + 0.5 * std::sin(s * 2.5)), ImVec2(-1, 0), label);
    ImGui::TextDisabled("the window stays live; the new session replaces this one when it is read");
    ImGui::EndPopup();
  }
}

}  // namespace sb::ui
