#include "widgets/workbench.hpp"

#include <GL/glew.h>
#include <imgui.h>

#include <algorithm>
#include <array>
#include <cfloat>
#include <chrono>
#include <thread>
#include <utility>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "widgets/keys.hpp"

namespace sb::ui {

namespace {
// Keyboard nudges.
constexpr double kNudgeM = 0.1e-3;
constexpr double kPushM = 0.05e-3;
constexpr double kTwistRad = 2.0 * M_PI / 180.0;
// Auto scale: the largest displacement is drawn as this fraction of the marker pitch.
constexpr double kAutoArrowFractionOfPitch = 0.9;
constexpr float kPad = 6.0f;
// The longest arrow drawn, in marker pitches: one and a half reaches past the next marker without
// crossing the panel (FOTS's 44 px at the default scene's gain would be 70 pitches).
constexpr double kMaxArrowPitches = 1.5;
constexpr ImGuiWindowFlags kFixed = ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoResize |
                                    ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoCollapse |
                                    ImGuiWindowFlags_NoBringToFrontOnFocus | ImGuiWindowFlags_NoSavedSettings;

GLuint upload_rgba(const cv::Mat& rgba, GLuint tex) {
  if (tex == 0) glGenTextures(1, &tex);
  glBindTexture(GL_TEXTURE_2D, tex);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, rgba.cols, rgba.rows, 0, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data);
  return tex;
}

// A neutral gel: warm grey, lit from the top left, as a GelSight image without contact looks.
cv::Mat neutral_gel_image(int w, int h) {
  cv::Mat img(h, w, CV_8UC4);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double s = 0.93 + 0.07 * (1.0 - (0.6 * x / w + 0.4 * y / h));
      img.at<cv::Vec4b>(y, x) = cv::Vec4b(cv::saturate_cast<uchar>(205 * s), cv::saturate_cast<uchar>(196 * s),
                                          cv::saturate_cast<uchar>(178 * s), 255);
    }
  return img;
}

ImTextureID as_texture_id(GLuint t) { return reinterpret_cast<ImTextureID>(static_cast<std::uintptr_t>(t)); }
}  // namespace

struct Workbench::Textures {
  GLuint neutral = 0;
  GLuint frame = 0;
  std::string frame_path;
  bool frame_ok = false;
  int neutral_w = 0, neutral_h = 0;
  ~Textures() {
    if (neutral) glDeleteTextures(1, &neutral);
    if (frame) glDeleteTextures(1, &frame);
  }
  ImTextureID neutral_for(int w, int h) {
    if (neutral == 0 || w != neutral_w || h != neutral_h) {
      neutral = upload_rgba(neutral_gel_image(w, h), neutral);
      neutral_w = w;
      neutral_h = h;
    }
    return as_texture_id(neutral);
  }
  ImTextureID frame_for(const std::string& path) {
    if (path != frame_path) {
      frame_path = path;
      const cv::Mat bgr = cv::imread(path, cv::IMREAD_COLOR);
      frame_ok = !bgr.empty();
      if (frame_ok) {
        cv::Mat rgba;
        cv::cvtColor(bgr, rgba, cv::COLOR_BGR2RGBA);
        frame = upload_rgba(rgba, frame);
      }
    }
    return frame_ok ? as_texture_id(frame) : nullptr;
  }
};

Workbench::Workbench(WorkbenchOptions options) : options_(options), textures_(std::make_unique<Textures>()) {}
Workbench::~Workbench() = default;

void Workbench::set_session(AppState* state, MeasuredData measured, std::string title, ReplayUi replay) {
  state_ = state;
  measured_ = std::move(measured);
  title_ = std::move(title);
  replay_ = std::move(replay);
  std::snprintf(replay_.dataset_buf, sizeof replay_.dataset_buf, "%s", replay_.dataset_dir.c_str());
  snap_ = state_->snapshot();
  edit_params_.clear();
  for (const auto& m : snap_.models) edit_params_.push_back(m.params);
  rmse_params_.clear();   // a new sample: its series is computed afresh
  corrected_job_.clear();
  corrected_started_ = false;
  viewport_.set_scene(*state_->sensor(), *state_->indenter());
  // Marker pitch: the smallest distance between two rest markers (for the automatic arrow scale).
  const auto& rest = state_->sensor()->markers_rest_px;
  double pitch = 1e9;
  for (std::size_t i = 0; i < rest.size(); ++i)
    for (std::size_t j = i + 1; j < rest.size(); ++j) pitch = std::min(pitch, (rest[i] - rest[j]).norm());
  marker_pitch_px_ = pitch < 1e9 && pitch > 0 ? pitch : 33.0;
  scale_.max_arrow_px = static_cast<float>(kMaxArrowPitches * marker_pitch_px_);
  last_drag_.reset();
  // The held auto scale starts again with the new session, from the sample's largest measurement.
  held_max_px_ = 0;
  sample_max_px_ = 0;
  for (const auto& frame : measured_.disp_px)
    for (const Vec2& d : frame)
      if (d.allFinite()) sample_max_px_ = std::max(sample_max_px_, d.norm());
}

const std::vector<Vec2>* Workbench::measured_at_step() const {
  const int k = snap_.step;
  if (k < 0 || k >= snap_.measured_steps || k >= static_cast<int>(measured_.disp_px.size())) return nullptr;
  return &measured_.disp_px[k];
}

void Workbench::auto_scale() {
  const auto max_of = [](const std::vector<Vec2>& d) {
    double m = 0;
    for (const Vec2& v : d)
      if (std::isfinite(v.x()) && std::isfinite(v.y())) m = std::max(m, v.norm());
    return m;
  };
  // The reference field sets the scale: the measurement when there is one, else the median of the
  // models' largest displacements (one model far off should not flatten the others).
  double max_px = 0;
  if (const auto* meas = measured_at_step()) {
    max_px = max_of(*meas);
  } else {
    std::vector<double> maxes;
    for (const auto& m : snap_.models) maxes.push_back(max_of(m.out.disp_px));
    if (!maxes.empty()) {
      std::sort(maxes.begin(), maxes.end());
      max_px = maxes[maxes.size() / 2];
    }
  }
  // Without a field yet keep the previous scale rather than blowing up the gain.
  constexpr double kMinFieldPx = 0.05;
  if (max_px < kMinFieldPx) return;
  // Arrows follow the frame (the legend's scale bar says how long a pixel is drawn) ...
  scale_.arrow_gain = static_cast<float>(std::clamp(kAutoArrowFractionOfPitch * marker_pitch_px_ / max_px, 0.2, 200.0));
  // ... and colours, held, only grow (from a sample's largest measurement on), so a colour keeps its meaning
  // through a drag or a replay (issue 34: the colour maximum went 2 -> 40 -> 10 px within one drag).
  if (hold_scale_) {
    held_max_px_ = std::max({held_max_px_, max_px, sample_max_px_});
    max_px = held_max_px_;
  }
  // The colour map tops out at a round number just above the reference's largest displacement.
  const double top = nice_floor(max_px);
  scale_.colour_max_px = static_cast<float>(top >= max_px ? top : (top * 2 >= max_px ? top * 2 : top * 5));
}

void Workbench::nudge(const Pose& delta_E, bool rotate_about_origin) {
  Pose X = last_drag_ ? *last_drag_ : snap_.X_EI;
  if (rotate_about_origin)
    X.linear() = delta_E.linear() * X.linear();  // about the indenter origin, axes of E
  X.translation() += delta_E.translation();
  state_->request_drag(X);
  last_drag_ = X;
}

void Workbench::apply_actions(WorkbenchRequest& req) {
  for (Action a : pressed_actions()) {
    switch (a) {
      case Action::PlayPause: state_->set_playing(!snap_.playing); break;
      case Action::StepForward: state_->request_seek(snap_.step + 1); break;
      case Action::StepBack: state_->request_seek(std::max(-1, snap_.step - 1)); break;
      case Action::Rewind: state_->request_seek(-1); break;
      case Action::End: state_->request_seek(snap_.num_steps - 1); break;
      case Action::NudgeXPlus: nudge(make_pose(Vec3(kNudgeM, 0, 0), Quat::Identity()), false); break;
      case Action::NudgeXMinus: nudge(make_pose(Vec3(-kNudgeM, 0, 0), Quat::Identity()), false); break;
      case Action::NudgeYPlus: nudge(make_pose(Vec3(0, kNudgeM, 0), Quat::Identity()), false); break;
      case Action::NudgeYMinus: nudge(make_pose(Vec3(0, -kNudgeM, 0), Quat::Identity()), false); break;
      case Action::PushIn: nudge(make_pose(Vec3(0, 0, -kPushM), Quat::Identity()), false); break;
      case Action::PullOut: nudge(make_pose(Vec3(0, 0, kPushM), Quat::Identity()), false); break;
      case Action::TwistPlus: nudge(make_pose(Vec3::Zero(), Quat(Eigen::AngleAxisd(kTwistRad, Vec3::UnitZ()))), true); break;
      case Action::TwistMinus: nudge(make_pose(Vec3::Zero(), Quat(Eigen::AngleAxisd(-kTwistRad, Vec3::UnitZ()))), true); break;
      case Action::CameraReset:
      case Action::CameraIso: viewport_.set_camera(CameraPreset::Iso); break;
      case Action::CameraTop: viewport_.set_camera(CameraPreset::Top); break;
      case Action::CameraSide: viewport_.set_camera(CameraPreset::Side); break;
      case Action::ArrowsLonger: auto_scale_ = false; scale_.arrow_gain *= 1.25f; break;
      case Action::ArrowsShorter: auto_scale_ = false; scale_.arrow_gain /= 1.25f; break;
      case Action::NextMarkerModel: marker_model_ = (marker_model_ + 1) % std::max<int>(1, snap_.models.size()); break;
      case Action::Screenshot: req.screenshot = true; break;
      case Action::ToggleHelp: show_help_ = !show_help_; break;
      case Action::SaveSession: req.save_session = std::string(session_path_); break;
      case Action::Quit: req.quit = true; break;
    }
  }
}

void Workbench::draw_controls(WorkbenchRequest& req) {
  ImGui::TextWrapped("%s", title_.c_str());
  ImGui::Separator();
  if (ImGui::CollapsingHeader("Replay", ImGuiTreeNodeFlags_DefaultOpen)) {
    const ReplayRequest r = replay_panel(snap_, replay_);
    if (r.toggle_play) {
      if (!snap_.playing && snap_.step >= snap_.num_steps - 1) state_->request_seek(-1);
      state_->set_playing(!snap_.playing);
    }
    if (r.seek_to != -2) state_->request_seek(r.seek_to);
    if (r.speed > 0) state_->set_speed(r.speed);
    if (r.open_sample) req.open_sample = replay_.sample_index;
    if (r.open_dataset) req.open_dataset = std::string(replay_.dataset_buf);
  }
  if (!measured_.disp_px.empty() && ImGui::CollapsingHeader("RMSE over time", ImGuiTreeNodeFlags_DefaultOpen))
    draw_rmse_plots();
  // Beside the RMSE plots: what the residual analysis says the model is missing.
  if (std::exchange(open_residual_section_, false)) ImGui::SetNextItemOpen(true);
  if (ImGui::CollapsingHeader("Residual")) draw_residual_panel(req);
  if (ImGui::CollapsingHeader("Indenter pose", ImGuiTreeNodeFlags_DefaultOpen)) {
    Pose X = last_drag_ && viewport_.dragging() ? *last_drag_ : snap_.X_EI;
    if (pose_panel(X)) {
      state_->request_drag(X);
      last_drag_ = X;
    }
    ImGui::TextDisabled("drag it in the 3D view; F1 for keys");
  }
  if (ImGui::CollapsingHeader("Display", ImGuiTreeNodeFlags_DefaultOpen)) draw_display_section(req);
  if (ImGui::CollapsingHeader("Parameters", ImGuiTreeNodeFlags_DefaultOpen)) {
    draw_variant_switches(req);
    ImGui::SetNextItemWidth(-110);
    ImGui::InputText("##params", params_path_, sizeof params_path_);
    ImGui::SameLine();
    if (ImGui::SmallButton("Load")) req.load_params = std::string(params_path_);
    ImGui::SameLine();
    if (ImGui::SmallButton("Save")) req.save_params = std::string(params_path_);
    draw_param_set_row(req);
    for (std::size_t m = 0; m < snap_.models.size() && m < edit_params_.size(); ++m) {
      const std::string& id = snap_.models[m].id;
      if (!ImGui::TreeNodeEx(id.c_str(), m == 0 ? ImGuiTreeNodeFlags_DefaultOpen : 0, "%s", display_name(id).c_str()))
        continue;
      // Slider edits go to a local copy that is sent as a whole; the snapshot catches up after the replay.
      const ParamSet published = default_params(id);
      if (param_panel(id, edit_params_[m], param_set_.params(id), show_published_ ? &published : nullptr))
        state_->request_params(m, edit_params_[m]);
      ImGui::TreePop();
    }
  }
  if (ImGui::CollapsingHeader("Fit")) draw_fit_panel();
  if (ImGui::CollapsingHeader("Session", ImGuiTreeNodeFlags_DefaultOpen)) draw_session_section(req);
}

// The session file's path (Save writes it, Open reads it; a scene or dataset typed here opens as in Replay
// without becoming the session file) and whether the work is saved.
void Workbench::draw_session_section(WorkbenchRequest& req) {
  ImGui::SetNextItemWidth(-110);
  // A click selects the whole path, so what is typed replaces it (a path typed into the middle of the old one
  // named a file nobody meant).
  ImGui::InputText("##session", session_path_, sizeof session_path_, ImGuiInputTextFlags_AutoSelectAll);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("session file (JSON): %s", session_path_);
  ImGui::SameLine();
  if (ImGui::SmallButton("Open##session")) req.open_session = std::string(session_path_);
  ImGui::SameLine();
  if (ImGui::SmallButton("Save##session")) req.save_session = std::string(session_path_);
  if (unsaved_) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.75f, 0.3f, 1.0f));
    ImGui::TextWrapped("unsaved changes (autosaved every 30 s; Ctrl+S saves)");
    ImGui::PopStyleColor();
  } else if (!saved_once_) {
    ImGui::PushTextWrapPos(0.0f);
    ImGui::TextDisabled("new session, not saved yet (Ctrl+S saves it)");
    ImGui::PopTextWrapPos();
  } else {
    ImGui::TextDisabled("saved");
  }
}

// Display: the shared arrow gain and colour scale (auto, held at the largest, or fixed), the 3D view's
// markers and camera, screenshots and the field export.
void Workbench::draw_display_section(WorkbenchRequest& req) {
  ImGui::Checkbox("auto scale", &auto_scale_);
  ImGui::SameLine();
  if (ImGui::Checkbox("hold colours", &hold_scale_)) held_max_px_ = 0;
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("on: the colour scale only grows (a dataset sample: from its largest measured |d|), so a\n"
                      "colour means the same from frame to frame; the arrows still follow each frame.\n"
                      "off: colours follow every frame. Untick auto scale to fix both at the sliders' values.");
  ImGui::SetNextItemWidth(-110);
  if (ImGui::SliderFloat("arrow gain", &scale_.arrow_gain, 0.2f, 200.0f, "%.3gx", ImGuiSliderFlags_Logarithmic))
    auto_scale_ = false;
  ImGui::SetNextItemWidth(-110);
  if (ImGui::SliderFloat("colour max", &scale_.colour_max_px, 0.05f, 50.0f, "%.3g px", ImGuiSliderFlags_Logarithmic))
    auto_scale_ = false;
  if (!snap_.models.empty()) {
    ImGui::SetNextItemWidth(-110);
    marker_model_ = std::clamp(marker_model_, 0, int(snap_.models.size()) - 1);
    if (ImGui::BeginCombo("3D markers", display_name(snap_.models[marker_model_].id).c_str())) {
      for (int i = 0; i < int(snap_.models.size()); ++i)
        if (ImGui::Selectable(display_name(snap_.models[i].id).c_str(), i == marker_model_)) marker_model_ = i;
      ImGui::EndCombo();
    }
  }
  if (ImGui::SmallButton("Top")) viewport_.set_camera(CameraPreset::Top);
  ImGui::SameLine();
  if (ImGui::SmallButton("Side")) viewport_.set_camera(CameraPreset::Side);
  ImGui::SameLine();
  if (ImGui::SmallButton("Iso")) viewport_.set_camera(CameraPreset::Iso);
  // Screenshot of the window or of one panel (PNG under screenshots/).
  ImGui::SetNextItemWidth(-110);
  const char* shown = screenshot_region_ > 0 && screenshot_region_ <= int(regions_.size())
                          ? regions_[screenshot_region_ - 1].name.c_str() : "whole window";
  if (ImGui::BeginCombo("##shotregion", shown)) {
    if (ImGui::Selectable("whole window", screenshot_region_ == 0)) screenshot_region_ = 0;
    for (int i = 0; i < int(regions_.size()); ++i)
      if (ImGui::Selectable(regions_[i].name.c_str(), screenshot_region_ == i + 1)) screenshot_region_ = i + 1;
    ImGui::EndCombo();
  }
  ImGui::SameLine();
  if (ImGui::SmallButton("Screenshot")) {
    req.screenshot = true;
    if (screenshot_region_ > 0 && screenshot_region_ <= int(regions_.size()))
      req.screenshot_region = regions_[screenshot_region_ - 1].name;
  }
  draw_export_row(req);
}

// HydroShear: the authors' | with the bonded-layer kernel | the stick zone | both | the contact variant (both,
// the layer's far field, contact-following tractions; issue 17, docs/effects.md);
// FOTS: original | re-implementation;
// TacSL: raw | normalised. The choice replaces that panel's model at
// the sync point (AppState::request_model), which replays the path to the current step.
void Workbench::draw_variant_switches(WorkbenchRequest& req) {
  struct Family { const char* label; std::vector<std::string> ids; };
  static const std::vector<Family> kFamilies{
      {"HydroShear", {"hydroshear", "hydroshear-layer", "hydroshear-stick", "hydroshear-layer-stick", "hydroshear-contact"}},
      {"FOTS", {"fots", "fots-reimpl"}},
      {"TacSL", {"tacsl", "tacsl-normalized"}}};
  const auto in_family = [](const Family& f, const std::string& id) {
    return std::find(f.ids.begin(), f.ids.end(), id) != f.ids.end();
  };
  std::string beside;   // a second HydroShear slot is the panel beside HydroShear's
  for (const Family& f : kFamilies) {
    bool first = true;
    for (int m = 0; m < static_cast<int>(snap_.models.size()); ++m) {
      const std::string& id = snap_.models[m].id;
      if (!in_family(f, id)) continue;
      if (!first) {
        beside = id;
        continue;
      }
      first = false;
      ImGui::SetNextItemWidth(-125);   // room for "HydroShear variant"
      if (ImGui::BeginCombo((std::string(f.label) + " variant").c_str(), display_name(id).c_str())) {
        for (const std::string& v : f.ids)
          if (ImGui::Selectable(display_name(v).c_str(), id == v) && id != v) req.switch_model = std::make_pair(m, v);
        ImGui::EndCombo();
      }
    }
  }
  // The corrected models beside the one they correct (issue 17): one more panel, its own parameters.
  ImGui::SetNextItemWidth(-125);
  if (ImGui::BeginCombo("beside HydroShear", beside.empty() ? "none" : display_name(beside).c_str())) {
    if (ImGui::Selectable("none", beside.empty()) && !beside.empty()) req.beside_hydroshear = "";
    for (const std::string& v : kFamilies.front().ids)
      if (ImGui::Selectable(display_name(v).c_str(), beside == v) && beside != v) req.beside_hydroshear = v;
    ImGui::EndCombo();
  }
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("A HydroShear variant in a field panel of its own, to compare a model-form correction\n"
                      "(docs/effects.md) with HydroShear as it is. Costs one more model per step.");
}

// Recomputes the RMSE-over-time series (worker thread) when the models' parameters differ from those of
// the last request, once the physics has applied them (no pending edits).
void Workbench::update_rmse_series() {
  if (measured_.disp_px.empty() || measured_.poses.empty() || state_->pending_edits() != 0) return;
  std::vector<std::vector<double>> values;
  for (const auto& m : snap_.models) values.push_back(m.params.values());
  if (values.empty() || values == rmse_params_) return;
  RmseSeriesRequest req;
  for (const auto& m : snap_.models) {
    req.model_ids.push_back(m.id);
    req.params.push_back(m.params);
  }
  req.sensor = state_->sensor();
  req.indenter = state_->indenter();
  req.path = measured_.poses;
  req.dt_s = snap_.dt_s;
  req.measured_px = measured_.disp_px;
  rmse_job_.start(std::move(req));
  rmse_params_ = std::move(values);
}

// Every model's field along the current path (replay or drags) as tsd/1 datasets, one per model; while
// the worker computes them, a progress bar and Cancel take the row's place.
void Workbench::draw_export_row(WorkbenchRequest& req) {
  const FieldExportStatus st = export_job_.status();
  if (st.running()) {
    char label[96];
    std::snprintf(label, sizeof label, "exporting  %s  %.0f %%", st.stage.c_str(), 100.0 * st.fraction);
    ImGui::ProgressBar(static_cast<float>(st.fraction), ImVec2(-70, 0), label);
    ImGui::SameLine();
    if (ImGui::SmallButton("Cancel##export")) export_job_.cancel();
    return;
  }
  ImGui::SetNextItemWidth(-110);
  ImGui::InputText("##exportdir", export_path_, sizeof export_path_);
  ImGui::SameLine();
  if (ImGui::SmallButton("Export fields")) req.export_fields = std::string(export_path_);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("writes <folder>/<model>/ (tsd/1) for every model");
}

void Workbench::start_export(FieldExportRequest request) {
  export_reported_ = false;
  export_job_.start(std::move(request));
}

// Once per export, when it has ended: what happened goes to the status bar.
void Workbench::report_export() {
  if (export_reported_) return;
  const FieldExportStatus st = export_job_.status();
  using Phase = FieldExportStatus::Phase;
  if (st.phase == Phase::Running || st.phase == Phase::Idle) return;
  export_reported_ = true;
  if (st.phase == Phase::Done)
    message_ = "exported " + std::to_string(st.written) + " fields (tsd/1) to " + st.dir;
  else if (st.phase == Phase::Cancelled)
    message_ = "export cancelled; nothing was written to " + st.dir;
  else
    message_ = "error: export to " + st.dir + ": " + st.error;
}

void Workbench::wait_for_background() const {
  while (rmse_job_.running()) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  corrected_job_.wait();
}

void Workbench::draw_rmse_plots() {
  const auto series = rmse_job_.result();
  if (series.size() != snap_.models.size()) {
    ImGui::TextDisabled(rmse_job_.running() ? "computing ..." : "no measured frames to compare");
    return;
  }
  const float width = ImGui::GetContentRegionAvail().x;
  for (std::size_t m = 0; m < series.size(); ++m) {
    // Frames where nothing measured moves do not count (core/calibration/metrics.hpp): drawn as 0.
    std::vector<float> v(series[m].size());
    double sum = 0;
    int n = 0;
    for (std::size_t k = 0; k < v.size(); ++k) {
      const bool counts = std::isfinite(series[m][k]);
      v[k] = counts ? static_cast<float>(series[m][k]) : 0.0f;
      if (counts) sum += series[m][k], ++n;
    }
    char overlay[96];
    std::snprintf(overlay, sizeof overlay, "%s  mean %.2f px", display_name(snap_.models[m].id).c_str(), n ? sum / n : 0.0);
    const ImVec2 p0 = ImGui::GetCursorScreenPos();
    const float h = 34.0f;
    ImGui::PlotLines(("##rmse" + std::to_string(m)).c_str(), v.data(), static_cast<int>(v.size()), 0, overlay, 0.0f,
                     FLT_MAX, ImVec2(width, h));
    if (!v.empty() && snap_.step >= 0) {   // the current frame
      const float x = p0.x + width * (static_cast<float>(std::min<std::size_t>(snap_.step, v.size() - 1)) + 0.5f) /
                                 static_cast<float>(v.size());
      ImGui::GetWindowDrawList()->AddLine(ImVec2(x, p0.y), ImVec2(x, p0.y + h), IM_COL32(255, 200, 80, 255), 1.5f);
    }
  }
}

// A set's name in the combo, with the sensor it was fitted on when that is not the GelSight Mini (read once
// per set: the combo lists them every frame while it is open).
std::string Workbench::param_set_label(const std::string& name) {
  auto it = param_set_labels_.find(name);
  if (it == param_set_labels_.end()) {
    std::string sensor;
    try {
      sensor = load_param_set(name).sensor_model();
    } catch (const std::exception&) {
      sensor.clear();   // a broken file is reported when chosen, not while listing
    }
    const bool other = !sensor.empty() && sensor != kDefaultSensorModel;
    it = param_set_labels_.emplace(name, other ? name + "  (" + sensor + ")" : name).first;
  }
  return it->second;
}

// The parameter set every model started from: a combo to start again from another, its provenance as a
// tooltip (what it was fitted on, by which command, its validation RMSE), and the published values.
void Workbench::draw_param_set_row(WorkbenchRequest& req) {
  ImGui::TextUnformatted("parameter set");
  ImGui::SameLine();
  ImGui::SetNextItemWidth(-1);
  if (ImGui::BeginCombo("##param_set", param_set_.name.c_str())) {
    for (const std::string& name : param_set_names())
      if (ImGui::Selectable(param_set_label(name).c_str(), name == param_set_.name) && name != param_set_.name)
        req.param_set = name;
    ImGui::EndCombo();
  }
  if (ImGui::IsItemHovered()) wrapped_tooltip(param_set_.summary());
  if (!param_set_mismatch_.empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.75f, 0.3f, 1.0f));
    ImGui::TextWrapped("%s", param_set_mismatch_.c_str());
    ImGui::PopStyleColor();
  }
  ImGui::Checkbox("show the published values", &show_published_);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("show the authors' published value beside each slider");
}

// Calibration on a worker thread (core/calibration/fit_job.hpp): the panel polls its status each frame.
void Workbench::draw_fit_panel() {
  if (fit_dataset_[0] == '\0' && !replay_.dataset_dir.empty())
    std::snprintf(fit_dataset_, sizeof fit_dataset_, "%s", replay_.dataset_dir.c_str());
  ImGui::SetNextItemWidth(-70);
  ImGui::InputTextWithHint("dataset##fit", "e.g. data:twin/twin_sphere35", fit_dataset_, sizeof fit_dataset_);
  if (snap_.models.empty()) return;
  fit_model_ = std::clamp(fit_model_, 0, static_cast<int>(snap_.models.size()) - 1);
  ImGui::SetNextItemWidth(-70);
  if (ImGui::BeginCombo("model##fit", display_name(snap_.models[fit_model_].id).c_str())) {
    for (int m = 0; m < static_cast<int>(snap_.models.size()); ++m)
      if (ImGui::Selectable(display_name(snap_.models[m].id).c_str(), m == fit_model_)) fit_model_ = m;
    ImGui::EndCombo();
  }
  ImGui::Checkbox("joint refinement", &fit_joint_);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("on (the default): the paper's stages, then every parameter jointly\noff: the paper's stages only");
  ImGui::SetNextItemWidth(-70);
  ImGui::SliderInt("iterations##fit", &fit_iterations_, 1, 100);

  const FitJobStatus st = fit_job_.status();
  if (st.running()) {
    const float frac = std::min(1.0f, static_cast<float>(st.iteration) / static_cast<float>(std::max(1, fit_iterations_)));
    char label[96];
    std::snprintf(label, sizeof label, "%s  %s  iter %d", st.phase == FitJobStatus::Phase::Loading ? "loading" : "fitting",
                  st.stage.c_str(), st.iteration);
    ImGui::ProgressBar(frac, ImVec2(-70, 0), label);
    ImGui::SameLine();
    if (ImGui::SmallButton("Cancel##fit")) fit_job_.cancel();
  } else if (ImGui::Button("Run fit (calibration split)")) {
    FitJobRequest req;
    req.dataset_dir = fit_dataset_;
    req.data_root = data_root_;
    req.model_id = snap_.models[fit_model_].id;
    req.start = snap_.models[fit_model_].params;
    req.joint = fit_joint_;
    req.max_iterations = fit_iterations_;
    fit_model_id_ = req.model_id;
    fit_start_params_ = req.start;   // the table's "start" column: what the fit started from, not the live sliders
    fit_result_handled_ = false;
    fit_job_.start(std::move(req));
  }
  if (!st.losses.empty()) draw_loss_plot(st.losses);
  if (st.phase == FitJobStatus::Phase::Failed) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1, 0.4f, 0.4f, 1));
    ImGui::TextWrapped("%s", st.error.c_str());
    ImGui::PopStyleColor();
  }
  if (!st.result || fit_result_handled_) return;
  const bool cancelled = st.phase == FitJobStatus::Phase::Cancelled;
  ImGui::Text("%s: calibration RMSE %.3f -> %.3f px", cancelled ? "cancelled (completed stages)" : "done",
              st.calibration_rmse_before_px, st.calibration_rmse_after_px);
  const ParamSet& after = st.result->params;
  std::size_t model = snap_.models.size();
  for (std::size_t m = 0; m < snap_.models.size(); ++m)
    if (snap_.models[m].id == fit_model_id_) model = m;
  if (model == snap_.models.size()) return;
  const ParamSet& before = fit_start_params_;
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
    }
    ImGui::EndTable();
  }
  if (ImGui::Button("Apply##fit")) {
    state_->request_params(model, after);   // applied at the sync point; the replay re-runs
    fit_result_handled_ = true;
  }
  ImGui::SameLine();
  if (ImGui::Button("Discard##fit")) fit_result_handled_ = true;
}

// The fit's loss per iteration with its axes: cost (Ceres, log of the largest and smallest) against iteration.
void Workbench::draw_loss_plot(const std::vector<float>& losses) {
  const auto [lo, hi] = std::minmax_element(losses.begin(), losses.end());
  char top[32], bottom[32];
  std::snprintf(top, sizeof top, "%.3g", double(*hi));
  std::snprintf(bottom, sizeof bottom, "%.3g", double(*lo));
  const float axis_w = std::max(ImGui::CalcTextSize(top).x, ImGui::CalcTextSize(bottom).x) + 6;
  const float h = 60.0f;
  ImGui::TextDisabled("Ceres cost per iteration (all stages)");
  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const ImU32 text = ImGui::GetColorU32(ImGuiCol_TextDisabled);
  dl->AddText(ImVec2(p0.x, p0.y), text, top);
  dl->AddText(ImVec2(p0.x, p0.y + h - ImGui::GetTextLineHeight()), text, bottom);
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

void Workbench::ask(std::string id, std::string text, std::vector<std::string> buttons) {
  question_id_ = std::move(id);
  question_text_ = std::move(text);
  question_buttons_ = std::move(buttons);
}

void Workbench::set_session_path(const std::string& path) {
  session_file_ = path;
  std::snprintf(session_path_, sizeof session_path_, "%s", path.c_str());
}

void Workbench::set_loading(std::string what) {
  if (loading_what_.empty() && !what.empty()) loading_since_ = std::chrono::steady_clock::now();
  loading_what_ = std::move(what);
}

void Workbench::clear_residual() {
  residual_.reset();
  show_residual_fields_ = false;
  corrected_job_.clear();
  corrected_started_ = false;
}

// While a session opens on its worker: a modal line with the elapsed time and a moving bar; the window keeps
// drawing (the old session plays on behind it) and takes no input until the new one is swapped in.
void Workbench::draw_loading() {
  if (loading_what_.empty()) return;
  ImGui::OpenPopup("##loading");
  const ImGuiViewport* vp = ImGui::GetMainViewport();
  ImGui::SetNextWindowPos(ImVec2(vp->Pos.x + vp->Size.x / 2, vp->Pos.y + vp->Size.y / 2), ImGuiCond_Always,
                          ImVec2(0.5f, 0.5f));
  ImGui::SetNextWindowSize(ImVec2(std::min(560.0f, vp->Size.x - 40), 0));
  if (ImGui::BeginPopupModal("##loading", nullptr, ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoResize)) {
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - loading_since_).count();
    ImGui::TextWrapped("opening %s ...", loading_what_.c_str());
    char label[32];
    std::snprintf(label, sizeof label, "%.1f s", s);
    // No fraction is known: a bar that sweeps back and forth says the work is alive.
    ImGui::ProgressBar(static_cast<float>(0.5 + 0.5 * std::sin(s * 2.5)), ImVec2(-1, 0), label);
    ImGui::TextDisabled("the window stays live; the new session replaces this one when it is read");
    ImGui::EndPopup();
  }
}

void Workbench::draw_question(WorkbenchRequest& req) {
  if (question_id_.empty()) return;
  ImGui::OpenPopup("##question");
  const ImGuiViewport* vp = ImGui::GetMainViewport();
  ImGui::SetNextWindowPos(ImVec2(vp->Pos.x + vp->Size.x / 2, vp->Pos.y + vp->Size.y / 2), ImGuiCond_Always,
                          ImVec2(0.5f, 0.5f));
  if (ImGui::BeginPopupModal("##question", nullptr, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoTitleBar)) {
    ImGui::TextUnformatted(question_text_.c_str());
    ImGui::Separator();
    // Enter answers with the first button, the one that keeps the user's work (Restore; Save and close).
    const bool enter = take_enter_press();
    for (std::size_t i = 0; i < question_buttons_.size(); ++i) {
      if (i > 0) ImGui::SameLine();
      if (ImGui::Button(question_buttons_[i].c_str(), ImVec2(110, 0)) || (i == 0 && enter)) {
        req.answer = std::make_pair(question_id_, static_cast<int>(i));
        question_id_.clear();
        ImGui::CloseCurrentPopup();
      }
    }
    if (!question_buttons_.empty()) ImGui::TextDisabled("Enter: %s", question_buttons_[0].c_str());
    ImGui::EndPopup();
  }
}

std::vector<std::string> Workbench::panel_names() const {
  std::vector<std::string> names;
  for (const auto& m : snap_.models) names.push_back(display_name(m.id));
  names.push_back(measured_.label);
  return names;
}

bool Workbench::set_enlarged(const std::string& panel) {
  if (!panel.empty()) {
    if (state_ != nullptr) snap_ = state_->snapshot();
    const auto names = panel_names();
    if (std::find(names.begin(), names.end(), panel) == names.end()) return false;
  }
  enlarged_ = panel;
  return true;
}

// Every model's (du, dv) of one marker, and the measurement's, beside the marker.
void Workbench::draw_marker_tooltip(int marker, ImVec2 at) {
  // Beside the marker, on the side with room (a tooltip placed by hand is not kept on screen by ImGui).
  const ImVec2 size = ImGui::GetMainViewport()->Size;
  const ImVec2 pivot(at.x > 0.6f * size.x ? 1.0f : 0.0f, at.y > 0.5f * size.y ? 1.0f : 0.0f);
  ImGui::SetNextWindowPos(ImVec2(at.x + (pivot.x > 0 ? -14.0f : 14.0f), at.y + (pivot.y > 0 ? -10.0f : 10.0f)),
                          ImGuiCond_Always, pivot);
  ImGui::BeginTooltip();
  ImGui::Text("marker %d", marker);
  if (ImGui::BeginTable("##markertip", 4, ImGuiTableFlags_SizingFixedFit)) {
    for (const char* h : {"", "du px", "dv px", "|d| px"}) {
      ImGui::TableNextColumn();
      ImGui::TextDisabled("%s", h);
    }
    for (const auto& [title, field] : shown_fields_) {
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(title.c_str());
      const bool have = field != nullptr && marker < static_cast<int>(field->size()) &&
                        (*field)[marker].allFinite();
      if (!have) {
        ImGui::TableNextColumn();
        ImGui::TextDisabled(field == nullptr || field->empty() ? "no field" : "lost");
        continue;
      }
      const Vec2 d = (*field)[marker];
      ImGui::TableNextColumn();
      ImGui::Text("%+.3f", d.x());
      ImGui::TableNextColumn();
      ImGui::Text("%+.3f", d.y());
      ImGui::TableNextColumn();
      ImGui::Text("%.3f", d.norm());
    }
    ImGui::EndTable();
  }
  ImGui::EndTooltip();
}

// The field panels and the 3D view in one grid that fills the right column (at 1280 x 800 three columns of
// ~310 px: a panel is read without enlarging it), or the enlarged panel alone in the whole area.
FieldGrid Workbench::field_grid(float width, float height) const {
  const auto* sensor = state_->sensor().get();
  const float aspect = float(sensor->camera.height_px) / float(sensor->camera.width_px);
  const float line = ImGui::GetTextLineHeightWithSpacing();
  const int cells = static_cast<int>(snap_.models.size()) + 2;   // the 3D view, the models, Measured
  FieldGrid g;
  g.cols = cells <= 4 ? 2 : 3;
  g.rows = (cells + g.cols - 1) / g.cols;
  const float avail_h = height - field_legend_height() - kPad;
  const float by_width = (width - kPad * (g.cols - 1)) / g.cols;
  const float by_height = ((avail_h - kPad * (g.rows - 1)) / g.rows - line - 4) / aspect;
  g.cell_w = std::max(80.0f, std::min(by_width, by_height));
  g.cell_h = line + g.cell_w * aspect + 4;
  g.left = (width - (g.cell_w * g.cols + kPad * (g.cols - 1))) / 2;
  return g;
}

// One model's (or the measurement's) panel input for this frame; `residual` holds measured - model when shown.
FieldPanelInput Workbench::panel_input(int i, const std::vector<Vec2>* measured, std::vector<Vec2>& residual) {
  const auto* sensor = state_->sensor().get();
  FieldPanelInput in;
  in.rest_px = &sensor->markers_rest_px;
  in.image_width_px = sensor->camera.width_px;
  in.image_height_px = sensor->camera.height_px;
  if (i < static_cast<int>(snap_.models.size())) {
    const ModelView& m = snap_.models[i];
    in.title = display_name(m.id);
    const std::vector<Vec2>* field = &m.out.disp_px;
    if (i == corrected_slot() && show_corrected_) {
      if (const auto* c = corrected_at_step()) {
        field = c;
        in.title = residual_->after_model;   // the loop's answer: the form and its effects
      } else {
        in.title += corrected_job_.running() ? " (correcting ...)" : "";
      }
    }
    in.disp_px = field;
    in.in_contact = &m.out.marker_in_contact;
    if (measured != nullptr && metrics_ && !field->empty()) in.metrics = metrics_(*field, *measured);
    if (show_residual_fields_ && measured != nullptr && !field->empty()) {
      residual = residual_field(*measured, *field);
      in.disp_px = &residual;
      in.title += " residual";
    }
    in.note = snap_.step < 0 ? "before the first step" : "";
    return in;
  }
  in.title = measured_.label;
  in.disp_px = measured;
  in.note = measured_.disp_px.empty() ? "no measurement (scene)"
            : snap_.step >= snap_.measured_steps ? "path edited: no measurement"
                                                 : "no measurement at this step";
  if (replay_.tracked_markers == 0) {   // an empty sample is said in words, not drawn as 0.00 px
    in.disp_px = nullptr;
    in.note = "0 of " + std::to_string(replay_.total_markers) + " markers tracked in this sample";
  }
  return in;
}

void Workbench::draw_fields(float width, float height) {
  const auto* sensor = state_->sensor().get();
  const int iw = sensor->camera.width_px, ih = sensor->camera.height_px;
  const auto* measured = measured_at_step();
  ImTextureID background = nullptr;
  if (snap_.step >= 0 && snap_.step < int(measured_.frame_paths.size()) && snap_.step < snap_.measured_steps)
    background = textures_->frame_for(measured_.frame_paths[snap_.step]);
  if (background == nullptr) background = textures_->neutral_for(iw, ih);

  const int n = static_cast<int>(snap_.models.size()) + 1;
  const auto names = panel_names();
  const int enlarged = static_cast<int>(std::find(names.begin(), names.end(), enlarged_) - names.begin());
  if (enlarged == n) enlarged_.clear();
  const bool one = !enlarged_.empty();
  const float line = ImGui::GetTextLineHeightWithSpacing();
  const FieldGrid grid = field_grid(width, height);
  // Enlarged: as wide as fits the area at the image's aspect, centred.
  const float pw = one ? std::min(width, (height - line - 4 - field_legend_height()) * float(iw) / float(ih)) : grid.cell_w;
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  if (!one) draw_view_cell(origin.x + grid.left, origin.y, grid.cell_w, grid.cell_h - 4);
  std::vector<std::vector<Vec2>> residuals(n);   // measured - model, when the residual view is on
  shown_fields_.clear();
  int hovered = -1;
  ImVec2 hovered_at;
  bool first_shown = true;
  for (int i = 0; i < n; ++i) {
    FieldPanelInput in = panel_input(i, measured, residuals[i]);
    in.background = background;
    if (i < n - 1 || measured != nullptr) shown_fields_.emplace_back(in.title, in.disp_px);
    if (one && i != enlarged) continue;
    const int cell = i + 1;
    const ImVec2 panel_top = one ? ImVec2(origin.x + (width - pw) / 2, origin.y)
                                 : ImVec2(origin.x + grid.left + (cell % grid.cols) * (grid.cell_w + kPad),
                                          origin.y + (cell / grid.cols) * (grid.cell_h + kPad));
    ImGui::SetCursorScreenPos(panel_top);
    ImGui::BeginGroup();
    in.highlight_marker = forced_hover_ >= 0 ? forced_hover_ : hovered_marker_;
    in.enlarged = one;
    ImGui::PushID(i);
    const FieldPanelResult r = draw_field_panel(in, scale_, pw, options_.interactive);
    if (r.toggle_enlarge) enlarged_ = one ? std::string() : names[i];
    // The model panel last clicked (or enlarged) is the one the 3D view colours its markers by.
    if ((r.clicked || r.toggle_enlarge) && i < n - 1) marker_model_ = i;
    if (r.hovered_marker >= 0 || (forced_hover_ >= 0 && first_shown && forced_hover_ < int(in.rest_px->size()))) {
      hovered = r.hovered_marker >= 0 ? r.hovered_marker : forced_hover_;
      const float zoom = pw / float(iw);
      const Vec2& rest = (*in.rest_px)[hovered];
      hovered_at = ImVec2(panel_top.x + float(rest.x()) * zoom, panel_top.y + line + float(rest.y()) * zoom);
    }
    regions_.push_back({names[i], panel_top.x, panel_top.y, pw, r.height});
    ImGui::PopID();
    ImGui::EndGroup();
    first_shown = false;
  }
  hovered_marker_ = hovered;
  const float legend_y = one ? origin.y + line + 4 + pw * float(ih) / float(iw) : origin.y + grid.rows * (grid.cell_h + kPad);
  ImGui::SetCursorScreenPos(ImVec2(origin.x + (one ? (width - pw) / 2 : grid.left), legend_y));
  draw_field_legend(scale_, pw / float(iw), one ? pw : width - 2 * grid.left);
  if (hovered >= 0) draw_marker_tooltip(hovered, hovered_at);
}

// The 3D view in the grid's first cell, with its legend over it (what the markers' colours, the tracked
// points' colours and their lines mean).
void Workbench::draw_view_cell(float x, float y, float w, float h) {
  ImGui::SetCursorScreenPos(ImVec2(x, y));
  viewport_.update(snap_, marker_model_, scale_.colour_max_px);
  regions_.push_back({"3D view", x, y, w, h});
  if (auto target = viewport_.draw(w, h, last_drag_ && viewport_.dragging() ? *last_drag_ : snap_.X_EI,
                                   options_.interactive)) {
    if (!last_drag_ || !target->isApprox(*last_drag_, 1e-12)) {
      state_->request_drag(*target);
      last_drag_ = target;
    }
  }
  draw_view_legend(ImVec2(x, y), w);
}

void Workbench::draw_view_legend(ImVec2 at, float width) {
  const std::string model = snap_.models.empty() ? std::string("-") : display_name(snap_.models[marker_model_].id);
  struct Item { ImU32 colour; std::string text; bool line; ImVec2 pos; };
  std::vector<Item> items = {
      {IM_COL32(230, 230, 120, 255), "markers: |d| of " + model + " (panel colours)", false, {}},
      {IM_COL32(60, 200, 90, 255), "stick", false, {}}, {IM_COL32(240, 150, 40, 255), "slip", false, {}},
      {IM_COL32(150, 150, 150, 255), "free (tracked points)", false, {}},
      {IM_COL32(220, 220, 220, 255), "line: a tracked point to its anchor", true, {}}};
  const float lh = ImGui::GetTextLineHeight();
  float x = 0, y = 0, right = 0;
  for (std::size_t k = 0; k < items.size(); ++k) {   // rows: the markers, the point states, the lines
    const float w = ImGui::CalcTextSize(items[k].text.c_str()).x + 14;
    if (k == 1 || k == 4 || (k > 0 && x + w > width - 12)) x = 0, y += lh + 2;
    items[k].pos = ImVec2(at.x + 6 + x, at.y + 4 + y);
    x += w + 10;
    right = std::max(right, x);
  }
  ImDrawList* dl = ImGui::GetWindowDrawList();
  dl->PushClipRect(at, ImVec2(at.x + width, at.y + y + lh + 12), true);
  dl->AddRectFilled(ImVec2(at.x + 2, at.y + 2), ImVec2(at.x + 6 + right, at.y + 6 + y + lh), IM_COL32(20, 20, 25, 170), 3.0f);
  for (const Item& it : items) {
    const float cy = it.pos.y + lh / 2;
    if (it.line) dl->AddLine(ImVec2(it.pos.x + 1, cy), ImVec2(it.pos.x + 10, cy), it.colour, 1.5f);
    else dl->AddCircleFilled(ImVec2(it.pos.x + 5, cy), 4.0f, it.colour);
    dl->AddText(ImVec2(it.pos.x + 14, it.pos.y), IM_COL32(240, 240, 240, 255), it.text.c_str());
  }
  dl->PopClipRect();
}

bool Workbench::animating() const {
  // An enlarged panel hides the 3D view: its pending re-render waits for the view to come back.
  return state_ != nullptr && (snap_.playing || !loading_what_.empty() || (enlarged_.empty() && viewport_.busy()) || state_->version() != snap_.version ||
                               state_->pending_edits() > 0 || export_job_.status().running() || !export_reported_);
}

WorkbenchRequest Workbench::draw(double frame_ms) {
  WorkbenchRequest req;
  if (state_ == nullptr) return req;
  snap_ = state_->snapshot();
  // Parameters changed elsewhere (loaded from a file) show up in the sliders.
  for (std::size_t m = 0; m < snap_.models.size() && m < edit_params_.size(); ++m)
    if (!ImGui::IsAnyItemActive() && edit_params_[m].values() != snap_.models[m].params.values() &&
        state_->pending_edits() == 0)
      edit_params_[m] = snap_.models[m].params;
  if (auto_scale_) auto_scale();
  update_rmse_series();
  update_corrected_series();
  report_export();
  if (options_.interactive && question_id_.empty() && loading_what_.empty()) apply_actions(req);

  const ImGuiViewport* vp = ImGui::GetMainViewport();
  const float W = vp->Size.x, H = vp->Size.y;
  const float line = ImGui::GetTextLineHeightWithSpacing();
  // As tall as the status text wrapped to the window's width (an error is read whole), at most four lines.
  const float status_text_h = ImGui::CalcTextSize(status_text(snap_, frame_ms, options_.show_timings, message_).c_str(),
                                                  nullptr, false, W - 2 * ImGui::GetStyle().WindowPadding.x).y;
  const float status_h = std::min(status_text_h, 4 * ImGui::GetTextLineHeight()) + line + 8 - ImGui::GetTextLineHeight();
  const float left_w = std::clamp(0.25f * W, 300.0f, 400.0f);
  const float right_w = W - left_w;

  ImGui::SetNextWindowPos(vp->Pos);
  ImGui::SetNextWindowSize(ImVec2(left_w, H - status_h));
  ImGui::Begin("Controls", nullptr, kFixed);
  draw_controls(req);
  ImGui::End();

  // The right column: the 3D view and every field panel in one grid (an enlarged panel alone).
  regions_.clear();
  ImGui::SetNextWindowPos(ImVec2(vp->Pos.x + left_w, vp->Pos.y));
  ImGui::SetNextWindowSize(ImVec2(right_w, H - status_h));
  ImGui::Begin("Fields", nullptr, kFixed | ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoScrollWithMouse);
  const ImVec2 inner = ImGui::GetContentRegionAvail();
  draw_fields(inner.x, inner.y);
  ImGui::End();

  ImGui::SetNextWindowPos(ImVec2(vp->Pos.x, vp->Pos.y + H - status_h));
  ImGui::SetNextWindowSize(ImVec2(W, status_h));
  ImGui::Begin("Status", nullptr, kFixed | ImGuiWindowFlags_NoScrollbar);
  status_bar(snap_, frame_ms, options_.show_timings, message_);
  ImGui::End();

  draw_help_overlay(&show_help_);
  draw_question(req);
  draw_loading();
  return req;
}

}  // namespace sb::ui
