#include "widgets/panels.hpp"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/effects/model_spec.hpp"
#include "core/models/model_family.hpp"
#include "core/workbench/value_check.hpp"
#include "widgets/text_field.hpp"

namespace sb::ui {

std::string elide(const std::string& text, float max_width) {
  if (ImGui::CalcTextSize(text.c_str()).x <= max_width) return text;
  std::string t = text;
  while (!t.empty() && ImGui::CalcTextSize((t + "..").c_str()).x > max_width) t.pop_back();
  return t + "..";
}

std::string display_name(const std::string& id) {
  if (const ModelForm* form = find_model_form(id)) return form->label;
  // A form with effects (the loop's answer): "HydroShear + dome_sway + skin_indentation".
  const ModelSpec spec = split_model_spec(id);
  const ModelForm* form = find_model_form(spec.form);
  if (form == nullptr || spec.effects.empty()) return id;
  std::string name = form->label;
  for (const std::string& e : spec.effects) name += " + " + e;
  return name;
}

namespace {
// A parameter's value as a slider over its range (logarithmic for a log-scale one). A value typed out of the
// range (Ctrl+click) is set to the bound with `note` saying so, never clamped silently; `note` is cleared by the
// next edit that needs none.
bool slider_control(ParamSet& params, std::size_t i, float width, std::string& note) {
  const ParamSpec& spec = params.specs()[i];
  float v = static_cast<float>(params[i]);
  const std::string format = spec.unit.empty() ? "%.4g" : "%.4g " + spec.unit;
  const bool log = spec.log_scale && spec.min > 0;
  ImGui::SetNextItemWidth(width);
  // No AlwaysClamp: ImGui would clamp a typed value before check_param_value could say so.
  if (!ImGui::SliderFloat("##v", &v, static_cast<float>(spec.min), static_cast<float>(spec.max), format.c_str(),
                          log ? ImGuiSliderFlags_Logarithmic : 0))
    return false;
  const ParamCheck check = check_param_value(spec, static_cast<double>(v));
  if (check.note != note && !check.note.empty()) std::fprintf(stderr, "note: %s\n", check.note.c_str());
  note = check.note;
  if (!check.accepted || check.value == params[i]) return false;
  params.set(i, check.value);
  return true;
}

// "[min, max] unit" of a parameter, for its slider's tooltip.
std::string range_text(const ParamSpec& spec) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "range [%g, %g]%s%s%s", spec.min, spec.max, spec.unit.empty() ? "" : " ",
                spec.unit.c_str(), spec.log_scale ? " (log scale)" : "");
  return buf;
}

// A switch (0 or 1) as a checkbox, in the slider's place.
bool switch_control(ParamSet& params, std::size_t i, float width) {
  bool on = params[i] >= 0.5;
  const float start = ImGui::GetCursorPosX();
  const bool clicked = ImGui::Checkbox("##on", &on);
  ImGui::SameLine(start + width);  // the reset buttons and names stay in one column
  ImGui::Dummy(ImVec2(0, 0));
  if (!clicked) return false;
  params.set(i, on ? 1.0 : 0.0);
  return true;
}
}  // namespace

void at_bound_mark(const ParamSpec& spec) {
  ImGui::SameLine();
  // Where the row has no room for the words (a long name beside the slider), a "|" in the same colour; the
  // tooltip says it whole either way.
  const bool room = ImGui::GetContentRegionAvail().x >= ImGui::CalcTextSize("at bound").x;
  ImGui::TextColored(kAtBoundColour, room ? "at bound" : "|");
  if (ImGui::IsItemHovered()) wrapped_tooltip(spec.name + " is at a bound of its " + range_text(spec));
}

void note_line(const std::string& note) {
  ImGui::PushStyleColor(ImGuiCol_Text, kAtBoundColour);
  ImGui::TextWrapped("%s", note.c_str());
  ImGui::PopStyleColor();
}

bool param_panel(const std::string& model_id, ParamSet& params, const ParamSet& reference, const ParamSet* published,
                 std::vector<std::string>* notes) {
  bool changed = false;
  ImGui::PushID(model_id.c_str());
  // The sliders leave room for the reset button and the longest name of this table (at least half the
  // width stays the slider's; a name that still does not fit is cut, and its tooltip gives it whole).
  const ImGuiStyle& style = ImGui::GetStyle();
  float name_w = 0;
  for (const ParamSpec& spec : params.specs()) name_w = std::max(name_w, ImGui::CalcTextSize(spec.name.c_str()).x);
  const float reset_w = ImGui::CalcTextSize("R").x + 2 * style.FramePadding.x;
  const float avail = ImGui::GetContentRegionAvail().x;
  const float slider_w = std::max(avail - name_w - reset_w - 2 * style.ItemSpacing.x, 0.5f * avail);
  std::vector<std::string> no_notes;
  if (notes == nullptr) notes = &no_notes;
  notes->resize(params.size());
  for (std::size_t i = 0; i < params.size(); ++i) {
    const ParamSpec& spec = params.specs()[i];
    ImGui::PushID(static_cast<int>(i));
    if (spec.is_switch)
      changed |= switch_control(params, i, slider_w);
    else
      changed |= slider_control(params, i, slider_w, (*notes)[i]);
    if (ImGui::IsItemHovered() && !spec.is_switch)
      wrapped_tooltip(range_text(spec) + (spec.help.empty() ? "" : "\n" + spec.help));
    else if (ImGui::IsItemHovered() && !spec.help.empty())
      wrapped_tooltip(spec.help);
    ImGui::SameLine();
    if (ImGui::SmallButton("R") && params[i] != reference[i]) {
      params.set(i, reference[i]);
      changed = true;
    }
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("reset to %g (the parameter set's value)", reference[i]);
    ImGui::SameLine();
    ImGui::TextUnformatted(spec.name.c_str());
    if (ImGui::IsItemHovered()) wrapped_tooltip(spec.name + (spec.help.empty() ? "" : ": " + spec.help));
    if (published != nullptr) {
      ImGui::SameLine();
      ImGui::TextDisabled("published %.4g", (*published)[i]);
    }
    if (at_bound(spec, params[i])) at_bound_mark(spec);
    if (!(*notes)[i].empty()) note_line((*notes)[i]);
    ImGui::PopID();
  }
  ImGui::PopID();
  return changed;
}

Vec3 rpy_deg_of(const Mat3& R) {
  // Extrinsic x-y-z (roll, pitch, yaw) = intrinsic z-y'-x'': R = Rz(yaw) Ry(pitch) Rx(roll).
  const Vec3 ypr = R.eulerAngles(2, 1, 0);
  Vec3 rpy(ypr[2], ypr[1], ypr[0]);
  // eulerAngles puts yaw in [0, pi]; prefer the equivalent triple with |pitch| <= pi/2, small angles near 0.
  if (std::abs(rpy[1]) > M_PI / 2) rpy = Vec3(rpy[0] - M_PI, M_PI - rpy[1], rpy[2] - M_PI);
  for (int i = 0; i < 3; ++i) rpy[i] = std::remainder(rpy[i], 2 * M_PI);
  return rpy * 180.0 / M_PI;
}

Mat3 rotation_from_rpy_deg(const Vec3& rpy_deg) {
  const Vec3 r = rpy_deg * M_PI / 180.0;
  return Rz(r.z()) * Ry(r.y()) * Rx(r.x());
}

bool pose_panel(Pose& X) {
  float xyz[3] = {float(X.translation().x() * 1e3), float(X.translation().y() * 1e3), float(X.translation().z() * 1e3)};
  const Vec3 rpy = rpy_deg_of(X.linear());
  float ang[3] = {float(rpy.x()), float(rpy.y()), float(rpy.z())};
  bool changed = false;
  ImGui::SetNextItemWidth(-70);
  if (ImGui::DragFloat3("xyz mm", xyz, 0.01f, -40.f, 40.f, "%.3f")) changed = true;
  ImGui::SetNextItemWidth(-70);
  if (ImGui::DragFloat3("rpy deg", ang, 0.1f, -180.f, 180.f, "%.2f")) changed = true;
  if (changed) {
    X.translation() = Vec3(xyz[0], xyz[1], xyz[2]) * 1e-3;
    X.linear() = rotation_from_rpy_deg(Vec3(ang[0], ang[1], ang[2]));
  }
  return changed;
}

// The Open row: a dataset folder, a scene or a session file, typed (data:..., or relative: the working folder,
// then the data root) or chosen from the list; Enter in the field opens too.
void open_row(ReplayUi& ui, ReplayRequest& req) {
  ImGui::SetNextItemWidth(-90);
  if (entered(input_text_with_hint("##dataset", "dataset, scene or session (data:twin/...)", ui.dataset_input,
                                   ImGuiInputTextFlags_EnterReturnsTrue | ImGuiInputTextFlags_AutoSelectAll)))
    req.open_dataset = true;
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip(
        "a tsd/1 dataset folder, a scene (scenes/*.json) or a session file;\n"
        "data:twin/twin_sphere35 is under the data root, and so is twin/twin_sphere35\n"
        "when the working folder has no such path");
  ImGui::SameLine(0, 2);
  if (ImGui::BeginCombo("##openlist", "", ImGuiComboFlags_NoPreview | ImGuiComboFlags_HeightLarge)) {
    for (const std::string& c : ui.choices)
      if (ImGui::Selectable(c.c_str())) {
        ui.dataset_input = c;
        req.open_dataset = true;
      }
    ImGui::EndCombo();
  }
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("recent, the scenes and the data root's datasets");
  ImGui::SameLine();
  if (ImGui::Button("Open", ImVec2(-1, 0))) req.open_dataset = true;
}

ReplayRequest replay_panel(const AppSnapshot& snap, ReplayUi& ui) {
  ReplayRequest req;
  open_row(ui, req);
  if (ui.tracked_markers == 0) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.45f, 0.35f, 1.0f));
    ImGui::TextWrapped(
        "no marker tracked in this sample (0 of %d): nothing measured to compare with. A TacTip "
        "import with fewer than 66 calibration samples (--max-samples) has no pin prior and "
        "loses every deep press's pins.",
        ui.total_markers);
    ImGui::PopStyleColor();
  }
  if (!ui.samples.empty()) {
    ImGui::SetNextItemWidth(-60);
    const char* current = ui.samples[std::clamp(ui.sample_index, 0, int(ui.samples.size()) - 1)].c_str();
    if (ImGui::BeginCombo("sample", current)) {
      for (int i = 0; i < int(ui.samples.size()); ++i)
        if (ImGui::Selectable(ui.samples[i].c_str(), i == ui.sample_index)) {
          ui.sample_index = i;
          req.open_sample = true;
        }
      ImGui::EndCombo();
    }
  }
  if (ImGui::Button(snap.playing ? "Pause" : "Play", ImVec2(60, 0))) req.toggle_play = true;
  ImGui::SameLine();
  if (ImGui::Button("|<")) req.seek_to = -1;
  ImGui::SameLine();
  if (ImGui::Button("<")) req.seek_to = std::max(-1, snap.step - 1);
  ImGui::SameLine();
  if (ImGui::Button(">")) req.seek_to = snap.step + 1;
  ImGui::SameLine();
  if (ImGui::Button(">|")) req.seek_to = snap.num_steps - 1;
  ImGui::SameLine();
  float speed = float(snap.speed);
  ImGui::SetNextItemWidth(-1);
  if (ImGui::SliderFloat("##speed", &speed, 0.05f, 20.0f, "speed %.2gx", ImGuiSliderFlags_Logarithmic))
    req.speed = speed;
  int step = snap.step;
  ImGui::SetNextItemWidth(-1);
  char label[64];
  // Step -1 is the state before the first step (nothing simulated yet): said in words, not as a step number.
  if (snap.step < 0)
    std::snprintf(label, sizeof label, "before the first step (of %d)", snap.num_steps - 1);
  else
    std::snprintf(label, sizeof label, "step %%d / %d  (t = %.2f s)", snap.num_steps - 1, snap.step * snap.dt_s);
  if (ImGui::SliderInt("##timeline", &step, -1, std::max(0, snap.num_steps - 1), label)) req.seek_to = step;
  return req;
}

std::string status_text(const AppSnapshot& snap, double frame_ms, bool show_timings, const std::string& message) {
  std::string text = message.empty() ? std::string() : message + "  |  ";
  char buf[128];
  if (snap.step < 0)
    std::snprintf(buf, sizeof buf, "before the first step (of %d)", snap.num_steps - 1);
  else
    std::snprintf(buf, sizeof buf, "step %d/%d", snap.step, snap.num_steps - 1);
  text += buf;
  if (show_timings) {
    for (const auto& m : snap.models) {
      std::snprintf(buf, sizeof buf, "  |  %s %.2f ms", display_name(m.id).c_str(), m.timing.mean_ms);
      text += buf;
    }
    std::snprintf(buf, sizeof buf, "  |  frame %.1f ms (%.0f fps)", frame_ms, frame_ms > 0 ? 1000.0 / frame_ms : 0.0);
    text += buf;
  }
  return text;
}

void status_bar(const AppSnapshot& snap, double frame_ms, bool show_timings, const std::string& message) {
  const bool error = message.rfind("error", 0) == 0 || message.rfind("autosave failed", 0) == 0;
  if (error) ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.55f, 0.45f, 1.0f));
  ImGui::TextWrapped("%s", status_text(snap, frame_ms, show_timings, message).c_str());
  if (error) ImGui::PopStyleColor();
  if (!message.empty() && ImGui::IsItemHovered()) wrapped_tooltip(message);
}

void wrapped_tooltip(const std::string& text) {
  ImGui::BeginTooltip();
  ImGui::PushTextWrapPos(ImGui::GetFontSize() * 30.0f);
  ImGui::TextUnformatted(text.c_str());
  ImGui::PopTextWrapPos();
  ImGui::EndTooltip();
}

}  // namespace sb::ui
