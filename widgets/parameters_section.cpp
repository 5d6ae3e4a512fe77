#include "widgets/parameters_section.hpp"

#include <imgui.h>

#include <algorithm>

#include "core/effects/model_spec.hpp"
#include "core/models/model_family.hpp"
#include "core/workbench/session_file.hpp"

#include "widgets/panels.hpp"
#include "widgets/text_field.hpp"

namespace sb::ui {

void ParametersSection::start_session(const AppSnapshot& snap) {
  edit_params_.clear();
  for (const auto& m : snap.models) edit_params_.push_back(m.params);
  notes_.assign(edit_params_.size(), {});
}

void ParametersSection::catch_up(const AppSnapshot& snap, const AppState& state) {
  for (std::size_t m = 0; m < snap.models.size() && m < edit_params_.size(); ++m)
    if (!ImGui::IsAnyItemActive() && edit_params_[m].values() != snap.models[m].params.values() &&
        state.pending_edits() == 0)
      edit_params_[m] = snap.models[m].params;
}

void ParametersSection::draw(const AppSnapshot& snap, AppState& state, WorkbenchRequest& req) {
  draw_variant_switches(snap, req);
  draw_file_row(req);
  draw_param_set_row(req);
  draw_sliders(snap, state);
}

// One combo per model family, over its forms as its descriptor lists them (core/models/model_family.hpp), e.g.
// HydroShear: the authors' | with the bonded-layer kernel | the stick zone | both | the contact variant;
// FOTS: original | re-implementation; TacSL: raw | normalised. The choice replaces that panel's model at
// the sync point (AppState::request_model), which replays the path to the current step.
void ParametersSection::draw_variant_switches(const AppSnapshot& snap, WorkbenchRequest& req) {
  // The loop's answer ("hydroshear+dome_sway+...") is of its form's family.
  const auto in_family = [](const ModelFamily& f, const std::string& id) {
    return find_model_family_of_form(split_model_spec(id).form) == &f;
  };
  std::string beside;  // a second HydroShear slot is the panel beside HydroShear's
  for (const ModelFamily& f : model_families()) {
    bool first = true;
    for (int m = 0; m < static_cast<int>(snap.models.size()); ++m) {
      const std::string& id = snap.models[m].id;
      if (!in_family(f, id)) continue;
      if (!first) {
        beside = id;
        continue;
      }
      first = false;
      ImGui::SetNextItemWidth(-125);  // room for "HydroShear variant"
      if (ImGui::BeginCombo((f.label + " variant").c_str(), display_name(id).c_str())) {
        for (const std::string& v : f.form_ids())
          if (ImGui::Selectable(display_name(v).c_str(), id == v) && id != v) req.switch_model = std::make_pair(m, v);
        ImGui::EndCombo();
      }
    }
  }
  // The corrected models beside the one they correct: one more panel, its own parameters.
  ImGui::SetNextItemWidth(-125);
  if (ImGui::BeginCombo("beside HydroShear", beside.empty() ? "none" : display_name(beside).c_str())) {
    if (ImGui::Selectable("none", beside.empty()) && !beside.empty()) req.beside_hydroshear = "";
    for (const std::string& v : model_family("hydroshear").form_ids())
      if (ImGui::Selectable(display_name(v).c_str(), beside == v) && beside != v) req.beside_hydroshear = v;
    if (!loop_answer_.empty() &&
        ImGui::Selectable(("the loop's answer: " + display_name(loop_answer_)).c_str(), beside == loop_answer_) &&
        beside != loop_answer_)
      req.beside_hydroshear = kBesideHydroshearAuto;
    ImGui::EndCombo();
  }
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip(
        "A HydroShear variant in a field panel of its own, to compare a model-form correction\n"
        "(docs/effects.md) with HydroShear as it is. Costs one more model per step.");
}

void ParametersSection::draw_file_row(WorkbenchRequest& req) {
  next_item_leaves_label_room();
  input_text("##params", file_);
  ImGui::SameLine();
  if (ImGui::SmallButton("Load")) req.load_params = file_;
  ImGui::SameLine();
  if (ImGui::SmallButton("Save")) req.save_params = file_;
}

// A set's name in the combo, with the sensor it was fitted on when that is not the GelSight Mini (read once
// per set: the combo lists them every frame while it is open).
std::string ParametersSection::param_set_label(const std::string& name) {
  auto it = labels_.find(name);
  if (it == labels_.end()) {
    std::string sensor;
    try {
      sensor = load_param_set(name).sensor_model();
    } catch (const std::exception&) {
      sensor.clear();  // a broken file is reported when chosen, not while listing
    }
    const bool other = !sensor.empty() && sensor != kDefaultSensorModel;
    it = labels_.emplace(name, other ? name + "  (" + sensor + ")" : name).first;
  }
  return it->second;
}

// The parameter set every model started from: a combo to start again from another, its provenance as a
// tooltip (what it was fitted on, by which command, its validation RMSE), and the published values.
void ParametersSection::draw_param_set_row(WorkbenchRequest& req) {
  ImGui::TextUnformatted("parameter set");
  ImGui::SameLine();
  ImGui::SetNextItemWidth(-1);
  if (ImGui::BeginCombo("##param_set", set_.name.c_str())) {
    for (const std::string& name : param_set_names())
      if (ImGui::Selectable(param_set_label(name).c_str(), name == set_.name) && name != set_.name)
        req.param_set = name;
    ImGui::EndCombo();
  }
  if (ImGui::IsItemHovered()) wrapped_tooltip(set_.summary());
  if (!mismatch_.empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.75f, 0.3f, 1.0f));
    ImGui::TextWrapped("%s", mismatch_.c_str());
    ImGui::PopStyleColor();
  }
  ImGui::Checkbox("show the published values", &show_published_);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("show the authors' published value beside each slider");
}

// One tree node of sliders per model (the first open).
void ParametersSection::draw_sliders(const AppSnapshot& snap, AppState& state) {
  for (std::size_t m = 0; m < snap.models.size() && m < edit_params_.size() && m < notes_.size(); ++m) {
    const std::string& id = snap.models[m].id;
    if (!ImGui::TreeNodeEx(id.c_str(), m == 0 ? ImGuiTreeNodeFlags_DefaultOpen : 0, "%s", display_name(id).c_str()))
      continue;
    // Slider edits go to a local copy that is sent as a whole; the snapshot catches up after the replay.
    const ParamSet published = default_params(id);
    if (param_panel(id, edit_params_[m], set_.params(id), show_published_ ? &published : nullptr, &notes_[m])) {
      if (slider_gesture_ == 0) slider_gesture_ = state.new_gesture();
      state.request_params(m, edit_params_[m], {"edit of " + display_name(id) + " parameters", slider_gesture_});
    }
    ImGui::TreePop();
  }
  if (!ImGui::IsAnyItemActive()) slider_gesture_ = 0;  // the slider let go: one drag of it is one undo entry
}

}  // namespace sb::ui
