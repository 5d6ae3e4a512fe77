// The Residual section (residual_section.hpp).
#include "widgets/residual_section.hpp"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/base/display_path.hpp"
#include "core/base/strings.hpp"
#include "core/effects/effects.hpp"
#include "widgets/panels.hpp"
#include "widgets/text_field.hpp"

namespace sb::ui {

namespace {
const ImVec4 kSelectedColour(0.45f, 0.85f, 0.45f, 1.0f);
}  // namespace

void ResidualSection::set(ResidualSummary summary, const std::string& data_root) {
  path_ = display_path(summary.file, data_root);
  residual_ = std::move(summary);
  restart_corrected();
  open_section_ = true;
}

void ResidualSection::clear() {
  residual_.reset();
  show_residual_fields_ = false;
  restart_corrected();
}

void ResidualSection::restart_corrected() {
  corrected_job_.clear();
  corrected_started_ = false;
}

bool ResidualSection::apply_base_params(const AppSnapshot& snap, AppState& state) const {
  if (!residual_) return false;
  for (std::size_t m = 0; m < snap.models.size(); ++m)
    if (snap.models[m].id == residual_->model_id) {
      state.request_params(m, fitted_base_params(*residual_));  // applied at the sync point
      return true;
    }
  return false;
}

int ResidualSection::corrected_slot(const AppSnapshot& snap) const {
  if (!residual_ || residual_->after_model == residual_->model_id) return -1;
  for (int m = 0; m < static_cast<int>(snap.models.size()); ++m)
    if (snap.models[m].id == residual_->model_id) return m;
  return -1;
}

void ResidualSection::update_corrected(const AppSnapshot& snap, const AppState& state, const std::vector<Pose>& poses) {
  if (!show_corrected_ || corrected_started_ || corrected_slot(snap) < 0 || poses.empty()) return;
  corrected_job_.start(make_corrected_model(*residual_, state.sensor(), state.indenter()), poses, snap.dt_s);
  corrected_started_ = true;
}

const std::vector<std::vector<Vec2>>* ResidualSection::corrected_series(std::string& message) {
  if (!show_corrected_ || !corrected_started_ || corrected_job_.running()) return nullptr;
  try {
    return &corrected_job_.result();
  } catch (const std::exception& e) {  // the worker failed: say so once, stop showing it
    message = std::string("corrected model: ") + e.what();
    show_corrected_ = false;
    corrected_job_.clear();
    return nullptr;
  }
}

const std::vector<Vec2>* ResidualSection::corrected_at_step(const AppSnapshot& snap, std::string& message) {
  const std::vector<std::vector<Vec2>>* series_ptr = corrected_series(message);
  if (series_ptr == nullptr) return nullptr;
  const auto& series = *series_ptr;
  const int k = snap.step;
  if (k < 0 || k >= snap.measured_steps || k >= static_cast<int>(series.size())) return nullptr;
  return &series[k];
}

// Where (against the contact edge, ahead of or behind the travel), when (phase) and under which load the
// base model is wrong, and in which direction: the analysis's contact-frame tables, one at a time.
void ResidualSection::draw_contact_frame_tables(const ResidualSummary& r) {
  if (r.contact_frame.empty() ||
      !ImGui::TreeNodeEx("where and when it is wrong (contact frame)", ImGuiTreeNodeFlags_DefaultOpen))
    return;
  contact_table_ = std::clamp(contact_table_, 0, static_cast<int>(r.contact_frame.size()) - 1);
  const auto short_name = [](const std::string& n) { return n.rfind("contact frame: ", 0) == 0 ? n.substr(15) : n; };
  ImGui::SetNextItemWidth(-1);
  if (ImGui::BeginCombo("##contact_table", short_name(r.contact_frame[contact_table_].name).c_str())) {
    for (int i = 0; i < static_cast<int>(r.contact_frame.size()); ++i)
      if (ImGui::Selectable(short_name(r.contact_frame[i].name).c_str(), i == contact_table_)) contact_table_ = i;
    ImGui::EndCombo();
  }
  const ContactFrameTableView& t = r.contact_frame[contact_table_];
  constexpr ImGuiTableFlags kFlags = ImGuiTableFlags_RowBg | ImGuiTableFlags_BordersInnerV |
                                     ImGuiTableFlags_SizingStretchProp;
  if (ImGui::BeginTable("##contact_frame", 4, kFlags)) {
    ImGui::TableSetupColumn(t.unit.empty() ? "bin" : ("bin " + t.unit).c_str(), ImGuiTableColumnFlags_WidthStretch,
                            1.6f);
    for (const char* c : {"RMS", "radial", "along"})
      ImGui::TableSetupColumn(c, ImGuiTableColumnFlags_WidthStretch, 1.0f);
    ImGui::TableHeadersRow();
    for (std::size_t b = 0; b < t.bins.size(); ++b) {
      if (t.count[b] == 0) continue;
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(t.bins[b].c_str());
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("%ld marker-frames", t.count[b]);
      ImGui::TableNextColumn();
      ImGui::Text("%.2f", t.rms_px[b]);
      for (double v : {t.mean_radial_px[b], t.mean_along_px[b]}) {
        ImGui::TableNextColumn();
        ImGui::Text("%+.2f", v);  // signed: a bias has a direction
      }
    }
    ImGui::EndTable();
  }
  ImGui::TextDisabled("px, measured - model; radial + outward, along + with the travel");
  ImGui::TreePop();
}

// How the measured field and the base model respond to one known input at a time (core/loop/input_response.hpp):
// a gain far from 1 is a magnitude the model misses, a shape error left after the gain a form it lacks.
void ResidualSection::draw_input_response_table(const ResidualSummary& r) {
  if (r.input_response.empty() || !ImGui::TreeNodeEx("response to the known inputs", ImGuiTreeNodeFlags_DefaultOpen))
    return;
  constexpr ImGuiTableFlags kFlags = ImGuiTableFlags_RowBg | ImGuiTableFlags_BordersInnerV |
                                     ImGuiTableFlags_SizingStretchProp;
  if (ImGui::BeginTable("##input_response", 5, kFlags)) {
    ImGui::TableSetupColumn("change", ImGuiTableColumnFlags_WidthStretch, 2.4f);
    for (const char* c : {"measured", "model", "gain", "shape"})
      ImGui::TableSetupColumn(c, ImGuiTableColumnFlags_WidthStretch, 1.0f);
    ImGui::TableHeadersRow();
    for (const auto& row : r.input_response) {
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(row.change.c_str());
      for (double v : {row.measured_rms_px, row.model_rms_px, row.gain, row.after_gain_rms_px}) {
        ImGui::TableNextColumn();
        ImGui::Text("%.2f", v);
      }
    }
    ImGui::EndTable();
  }
  ImGui::TextDisabled("px RMS; gain = measured / model;");
  ImGui::TextDisabled("shape = px left after the gain");
  ImGui::TextDisabled("the inputs alone predict validation to %.2f px", r.inputs_only_rmse_px);
  ImGui::TreePop();
}

// The base model's mean residual per bin of depth, travel and tilt direction: a whole-field shift that follows a
// direction (the TacTip's dome sway) reads off the shift column; the maps are the report's mean_by_ PNGs.
void ResidualSection::draw_binned_means_table(const ResidualSummary& r) {
  if (r.binned_means.empty() || !ImGui::TreeNodeEx("mean residual per bin", ImGuiTreeNodeFlags_DefaultOpen)) return;
  constexpr ImGuiTableFlags kFlags = ImGuiTableFlags_RowBg | ImGuiTableFlags_BordersInnerV |
                                     ImGuiTableFlags_SizingStretchProp;
  if (ImGui::BeginTable("##binned_means", 3, kFlags)) {
    ImGui::TableSetupColumn("bin", ImGuiTableColumnFlags_WidthStretch, 1.9f);
    ImGui::TableSetupColumn("RMS", ImGuiTableColumnFlags_WidthStretch, 0.7f);
    ImGui::TableSetupColumn("shift x y", ImGuiTableColumnFlags_WidthStretch, 1.4f);
    ImGui::TableHeadersRow();
    for (const auto& b : r.binned_means) {
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      const std::string first_word = b.covariate.substr(0, b.covariate.find(' '));
      ImGui::Text("%s %s", first_word == "penetration" ? "depth" : first_word.c_str(), b.bin.c_str());
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s: %s, %ld frames", b.covariate.c_str(), b.bin.c_str(), b.frames);
      ImGui::TableNextColumn();
      ImGui::Text("%.2f", b.rms_px);
      ImGui::TableNextColumn();
      ImGui::Text("%+.1f %+.1f", b.shift_px.x(), b.shift_px.y());
    }
    ImGui::EndTable();
  }
  ImGui::TextDisabled("px, measured - model, mean over the bin's");
  ImGui::TextDisabled("frames; shift: its mean over the markers");
  ImGui::TextDisabled("(maps: the report's mean_by_ PNGs)");
  ImGui::TreePop();
}

void ResidualSection::draw(const AppSnapshot& snap, AppState& state, bool have_poses, std::string& message,
                           WorkbenchRequest& req) {
  ImGui::SetNextItemWidth(-60);
  input_text("##residual", path_);
  ImGui::SameLine();
  if (ImGui::SmallButton("Load##residual")) req.load_residual = path_;
  if (!residual_) {
    ImGui::TextDisabled("a report of: shearbench residual --json FILE");
    return;
  }
  const ResidualSummary& r = *residual_;
  draw_summary(r);
  draw_candidates(r);
  draw_contact_frame_tables(r);
  draw_input_response_table(r);
  draw_binned_means_table(r);
  draw_switches(snap, state, have_poses, message);
}

// The model and dataset, the RMSE before and after, and the answer with its effects.
void ResidualSection::draw_summary(const ResidualSummary& r) const {
  ImGui::TextWrapped("%s on %s", display_name(r.model_id).c_str(), r.dataset.c_str());
  const double change = 100.0 * (r.after_rmse_px - r.before_rmse_px) / r.before_rmse_px;
  ImGui::Text("validation RMSE %.3f -> %.3f px (%+.1f %%)", r.before_rmse_px, r.after_rmse_px, change);
  ImGui::TextWrapped("answer: %s", r.answer_labelled.c_str());
  if (ImGui::IsItemHovered())
    wrapped_tooltip(
        "The model the analysis found: the selected model form (" +
        (r.model_form.empty() ? std::string("none, so the base") : r.model_form) + ") with the selected effects (" +
        (r.selected.empty() ? std::string("none") : join(r.selected, " + ")) +
        "), fitted jointly. Load it anywhere as --model " + r.after_model + " with the report's _params.json file.");
  ImGui::Text("effects: %s", r.selected.empty() ? "nothing selected" : join(r.selected, " + ").c_str());
  draw_evidence(r);
}

// Each selected effect: found by its evidence, or a correction of unshown cause; and the answer's parameters at a
// bound (model-form symptoms of the answer itself).
void ResidualSection::draw_evidence(const ResidualSummary& r) const {
  for (const auto& v : r.selected_evidence) {
    if (!v.recorded) continue;
    const char* label = v.found ? "found" : "correction of unshown cause";
    if (v.found) ImGui::PushStyleColor(ImGuiCol_Text, kSelectedColour);
    ImGui::BulletText("%s: %s", v.effect.c_str(), label);
    if (v.found) ImGui::PopStyleColor();
    if (ImGui::IsItemHovered())
      wrapped_tooltip(v.evidence + (v.found ? std::string()
                                            : "\n\nIt lowers the held-out error, but its own signature is not in the "
                                              "data: a correction the model's form needs, not a measured effect."));
  }
  for (const auto& b : r.answer_at_bound)
    ImGui::BulletText("model-form symptom: %s = %.3g at its %s bound%s", b.param.c_str(), b.value, b.bound.c_str(),
                      b.is_default ? " (no-effect default)" : "");
}

// The ranked candidates: gain, its confidence interval and the verdict (the selected ones in green).
void ResidualSection::draw_candidates(const ResidualSummary& r) const {
  constexpr ImGuiTableFlags kTable = ImGuiTableFlags_RowBg | ImGuiTableFlags_BordersInnerV |
                                     ImGuiTableFlags_SizingStretchProp;
  if (!ImGui::BeginTable("##candidates", 4, kTable)) return;
  ImGui::TableSetupColumn("effect", ImGuiTableColumnFlags_WidthStretch, 1.7f);
  ImGui::TableSetupColumn("gain%", ImGuiTableColumnFlags_WidthStretch, 0.75f);
  ImGui::TableSetupColumn("95 % CI", ImGuiTableColumnFlags_WidthStretch, 1.3f);
  ImGui::TableSetupColumn("why", ImGuiTableColumnFlags_WidthStretch, 1.2f);
  ImGui::TableHeadersRow();
  for (const auto& c : r.candidates) {
    const bool selected = std::find(r.selected.begin(), r.selected.end(), c.effect) != r.selected.end();
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    // The id with spaces, so a long one wraps in a narrow panel instead of being cut.
    std::string label = c.effect;
    std::replace(label.begin(), label.end(), '_', ' ');
    if (selected) ImGui::PushStyleColor(ImGuiCol_Text, kSelectedColour);
    ImGui::TextWrapped("%s%s", label.c_str(), selected ? " *" : "");
    if (selected) ImGui::PopStyleColor();
    if (ImGui::IsItemHovered()) wrapped_tooltip(c.effect + ": " + make_effect(c.effect)->physics() + "\n\n" + c.reason);
    ImGui::TableNextColumn();
    if (std::isfinite(c.improvement_pct))
      ImGui::Text("%+.1f", c.improvement_pct);
    else
      ImGui::TextDisabled("-");
    ImGui::TableNextColumn();
    if (std::isfinite(c.ci95_low_pct))
      ImGui::Text("[%.1f, %.1f]", c.ci95_low_pct, c.ci95_high_pct);
    else
      ImGui::TextDisabled("-");
    ImGui::TableNextColumn();
    ImGui::PushStyleColor(ImGuiCol_Text, selected ? kSelectedColour : ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
    ImGui::TextWrapped("%s", c.verdict.c_str());
    ImGui::PopStyleColor();
    if (ImGui::IsItemHovered()) wrapped_tooltip(c.reason);
  }
  ImGui::EndTable();
}

// The residual fields, the fitted base parameters, and the corrected model in the analysed model's panel.
void ResidualSection::draw_switches(const AppSnapshot& snap, AppState& state, bool have_poses, std::string& message) {
  const ResidualSummary& r = *residual_;
  ImGui::Checkbox("residual fields (measured - model)", &show_residual_fields_);
  if (ImGui::SmallButton("Apply the fitted base parameters")) {
    if (!apply_base_params(snap, state)) message = display_name(r.model_id) + " is not one of the shown models";
  }
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip(
        "%s's parameters as the analysis fitted them without effects:\nthe fair reference for the corrected model",
        display_name(r.model_id).c_str());
  const int slot = corrected_slot(snap);
  if (r.after_model == r.model_id) {
    ImGui::TextDisabled("nothing selected: no corrected model");
  } else if (slot < 0) {
    ImGui::TextDisabled("%s is not one of the shown models", display_name(r.model_id).c_str());
  } else {
    ImGui::Checkbox(("show " + r.after_model).c_str(), &show_corrected_);
    if (ImGui::IsItemHovered())
      wrapped_tooltip(display_name(r.model_id) + "'s panel shows the loop's answer instead, at its fitted parameters");
    if (show_corrected_ && !have_poses)
      ImGui::TextDisabled("(needs a replay with measurements)");
    else if (show_corrected_ && corrected_job_.running())
      ImGui::TextDisabled("computing the corrected fields ...");
  }
}

}  // namespace sb::ui
