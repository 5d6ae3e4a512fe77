#include "widgets/workbench.hpp"

#include <GL/glew.h>
#include <imgui.h>

#include <algorithm>
#include <array>
#include <cfloat>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <thread>
#include <utility>

#include "core/workbench/column_layout.hpp"
#include "core/workbench/report_dataset.hpp"
#include "core/workbench/unsaved_work.hpp"
#include "widgets/keys.hpp"
#include "widgets/replay_section.hpp"

namespace sb::ui {

namespace {
// Keyboard nudges.
constexpr double kNudgeM = 0.1e-3;
constexpr double kPushM = 0.05e-3;
constexpr double kTwistRad = 2.0 * M_PI / 180.0;
constexpr float kPad = 6.0f;
constexpr ImGuiWindowFlags kFixed = ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoMove |
                                    ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoBringToFrontOnFocus |
                                    ImGuiWindowFlags_NoSavedSettings;

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

// ImGui names a texture by a pointer-sized id; OpenGL's are integers.
ImTextureID as_texture_id(GLuint t) {
  return reinterpret_cast<ImTextureID>(static_cast<std::uintptr_t>(t));  // NOLINT(performance-no-int-to-ptr)
}
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
  replay_.dataset_input = replay_.dataset_dir;
  snap_ = state_->snapshot();
  parameters_.start_session(snap_);
  rmse_.reset();  // a new sample: its series is computed afresh
  residual_.restart_corrected();
  viewport_.set_scene(*state_->sensor(), *state_->indenter());
  display_.start_session(state_->sensor()->markers_rest_px, measured_.disp_px, dataset_name(replay_.dataset_dir));
  pose_.reset();
}

const std::vector<Vec2>* Workbench::measured_at_step() const {
  const int k = snap_.step;
  if (k < 0 || k >= snap_.measured_steps || k >= static_cast<int>(measured_.disp_px.size())) return nullptr;
  return &measured_.disp_px[k];
}

void Workbench::apply_actions(WorkbenchRequest& req) {
  for (Action a : pressed_actions()) apply_action(a, req);
}

void Workbench::apply_action(Action action, WorkbenchRequest& req) {
  const auto move = [&](const Vec3& by) {
    say_if_path_replaced("nudge");
    pose_.nudge(make_pose(by, Quat::Identity()), false, snap_, *state_);
  };
  const auto twist = [&](double rad) {
    say_if_path_replaced("nudge");
    pose_.nudge(make_pose(Vec3::Zero(), Quat(Eigen::AngleAxisd(rad, Vec3::UnitZ()))), true, snap_, *state_);
  };
  switch (action) {
    case Action::kPlayPause: state_->set_playing(!snap_.playing); break;
    case Action::kStepForward: state_->request_seek(snap_.step + 1); break;
    case Action::kStepBack: state_->request_seek(std::max(-1, snap_.step - 1)); break;
    case Action::kRewind: state_->request_seek(-1); break;
    case Action::kEnd: state_->request_seek(snap_.num_steps - 1); break;
    case Action::kNudgeXPlus: move(Vec3(kNudgeM, 0, 0)); break;
    case Action::kNudgeXMinus: move(Vec3(-kNudgeM, 0, 0)); break;
    case Action::kNudgeYPlus: move(Vec3(0, kNudgeM, 0)); break;
    case Action::kNudgeYMinus: move(Vec3(0, -kNudgeM, 0)); break;
    case Action::kPushIn: move(Vec3(0, 0, -kPushM)); break;
    case Action::kPullOut: move(Vec3(0, 0, kPushM)); break;
    case Action::kTwistPlus: twist(kTwistRad); break;
    case Action::kTwistMinus: twist(-kTwistRad); break;
    case Action::kCameraReset:
    case Action::kCameraIso: viewport_.set_camera(CameraPreset::kIso); break;
    case Action::kCameraTop: viewport_.set_camera(CameraPreset::kTop); break;
    case Action::kCameraSide: viewport_.set_camera(CameraPreset::kSide); break;
    case Action::kArrowsLonger: display_.lengthen_arrows(true); break;
    case Action::kArrowsShorter: display_.lengthen_arrows(false); break;
    case Action::kNextMarkerModel: display_.next_marker_model(static_cast<int>(snap_.models.size())); break;
    case Action::kScreenshot: req.screenshot = true; break;
    case Action::kToggleHelp: show_help_ = !show_help_; break;
    case Action::kSaveSession: req.save_session = session_.field(); break;
    case Action::kUndo: undo(req); break;
    case Action::kRedo: state_->request_redo(); break;
    case Action::kQuit: req.quit = true; break;
  }
}

// A drag or nudge replaces the path after the step shown: when that drops recorded steps, the status bar says
// so and how to get them back (the undo history keeps the old path).
void Workbench::say_if_path_replaced(const char* by) {
  if (snap_.step + 1 < snap_.num_steps && !viewport_.dragging())
    message_ = std::string("path replaced by your ") + by + "; Ctrl+Z brings it back";
}

// Undo / Redo with what they would take back, as the tooltip names it.
void Workbench::write_display_choices(SessionFile& f) const {
  const AppSnapshot snap = state_->snapshot();
  const int m = display_.marker_model();
  // The first panel's model is the default: left out, as a file from before the choice was kept reads.
  f.marker_model = m > 0 && m < static_cast<int>(snap.models.size()) ? snap.models[m].id : "";
  f.colour_map = display_.scale().map;
  f.frame_backdrops = backdrops_.chosen();
}

void Workbench::read_display_choices(const SessionFile& f) {
  const AppSnapshot snap = state_->snapshot();
  display_.set_marker_model(0);
  for (int m = 0; m < static_cast<int>(snap.models.size()); ++m)
    if (snap.models[m].id == f.marker_model) display_.set_marker_model(m);
  display_.scale().map = f.colour_map;
  backdrops_.assign(f.frame_backdrops);
}

// The session's own edits first; with none left, the open that replaced unsaved work.
void Workbench::undo(WorkbenchRequest& req) {
  if (snap_.undo_label.empty() && !open_undo_.empty())
    req.undo_open = true;
  else
    state_->request_undo();
}

void Workbench::draw_undo_row(WorkbenchRequest& req) {
  const auto button = [this, &req](const char* label, const std::string& what, bool undo) {
    ImGui::BeginDisabled(what.empty());
    // Small: on the pose section's last line, so the column below keeps its place.
    if (ImGui::SmallButton(label)) undo ? this->undo(req) : state_->request_redo();
    ImGui::EndDisabled();
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
      ImGui::SetTooltip("%s",
                        what.empty()
                            ? (undo ? "nothing to undo" : "nothing to redo")
                            : ((undo ? "undo: " : "redo: ") + what + (undo ? " (Ctrl+Z)" : " (Ctrl+Shift+Z)")).c_str());
  };
  button("Undo", snap_.undo_label.empty() ? open_undo_ : snap_.undo_label, true);
  ImGui::SameLine();
  button("Redo", snap_.redo_label, false);
}

// Where a model's panel shows the residual loop's answer, its RMSE row shows the answer's too (one model per view).
RmseRowOverride Workbench::corrected_rmse_row() {
  const int slot = residual_.corrected_slot(snap_);
  if (slot < 0 || !residual_.corrected_shown()) return {};
  const auto* series = residual_.corrected_series(message_);
  if (series == nullptr) return {};
  return {slot, residual_.corrected_title(), rmse_of_fields(*series, measured_.disp_px)};
}

// The RMSE timeline's CSV goes beside the session file (the folder the workbench writes into, never the
// working folder): rmse_<dataset>_<sample>.csv.
std::string Workbench::rmse_csv_path() const {
  const std::string session = session_.file().empty() ? default_session_path() : session_.file();
  std::string name = "rmse";
  const auto dataset = std::filesystem::path(replay_.dataset_dir).filename().string();
  if (!dataset.empty()) name += "_" + dataset;
  if (replay_.sample_index >= 0 && replay_.sample_index < static_cast<int>(replay_.samples.size()))
    name += "_" + replay_.samples[replay_.sample_index];
  return (std::filesystem::path(session).parent_path() / (name + ".csv")).string();
}

// The control column: every section under its header, in a fixed order.
void Workbench::draw_controls(WorkbenchRequest& req) {
  ImGui::TextWrapped("%s", title_.c_str());
  ImGui::Separator();
  if (ImGui::CollapsingHeader("Replay", ImGuiTreeNodeFlags_DefaultOpen)) replay_section(snap_, replay_, *state_, req);
  if (!measured_.disp_px.empty() && ImGui::CollapsingHeader("RMSE over time", ImGuiTreeNodeFlags_DefaultOpen))
    rmse_.draw(snap_, *state_, rmse_csv_path(), message_, corrected_rmse_row());
  // Beside the RMSE plots: what the residual analysis says the model is missing.
  if (residual_.take_open_request()) ImGui::SetNextItemOpen(true);
  if (ImGui::CollapsingHeader("Residual")) residual_.draw(snap_, *state_, !measured_.poses.empty(), message_, req);
  if (ImGui::CollapsingHeader("Indenter pose", ImGuiTreeNodeFlags_DefaultOpen)) {
    pose_.draw(snap_, viewport_.dragging(), *state_);
    if (options_.interactive) {  // a headless render has nothing to undo: its image stays as it was
      ImGui::SameLine();
      draw_undo_row(req);
    }
  }
  if (ImGui::CollapsingHeader("Display", ImGuiTreeNodeFlags_DefaultOpen)) {
    display_.draw(snap_, viewport_, regions_, req);
    export_.draw(req);
  }
  if (ImGui::CollapsingHeader("Parameters", ImGuiTreeNodeFlags_DefaultOpen)) parameters_.draw(snap_, *state_, req);
  if (ImGui::CollapsingHeader("Fit")) fit_.draw(snap_, *state_, replay_.dataset_dir);
  if (ImGui::CollapsingHeader("Session", ImGuiTreeNodeFlags_DefaultOpen)) session_.draw(req);
}

std::vector<std::string> Workbench::panel_names() const {
  std::vector<std::string> names;
  for (const auto& m : snap_.models) names.push_back(display_name(m.id));
  names.push_back(measured_.label);
  for (const auto& b : measured_.beside) names.push_back(b.label);
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
      const bool have = field != nullptr && marker < static_cast<int>(field->size()) && (*field)[marker].allFinite();
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
  // The 3D view, the models, Measured and the other sensors of a multi-sensor log.
  const int cells = static_cast<int>(snap_.models.size() + measured_.beside.size()) + 2;
  FieldGrid g;
  g.cols = cells <= 4 ? 2 : 3;
  g.rows = (cells + g.cols - 1) / g.cols;
  g.legend_h = field_legend_height();
  const float avail_h = height - g.legend_h - kPad;
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
    if (i == residual_.corrected_slot(snap_) && residual_.corrected_shown()) {
      if (const auto* c = residual_.corrected_at_step(snap_, message_)) {
        field = c;
        in.title = residual_.corrected_title();  // the loop's answer: the form and its effects
      } else {
        in.title += residual_.correcting() ? " (correcting ...)" : "";
      }
    }
    in.disp_px = field;
    in.in_contact = &m.out.marker_in_contact;
    if (measured != nullptr && metrics_ && !field->empty()) in.metrics = metrics_(*field, *measured);
    if (residual_.residual_fields_shown() && measured != nullptr && !field->empty()) {
      residual = residual_field(*measured, *field);
      in.disp_px = &residual;
      in.title += " residual";
    }
    in.note = snap_.step < 0 ? "before the first step" : "";
    return in;
  }
  if (const int b = i - static_cast<int>(snap_.models.size()) - 1; b >= 0) {  // another sensor of the log
    const auto& other = measured_.beside[b];
    in.title = other.label;
    const int k = snap_.step;
    in.disp_px = k >= 0 && k < snap_.measured_steps && k < static_cast<int>(other.disp_px.size()) ? &other.disp_px[k]
                                                                                                  : nullptr;
    in.note = "no measurement at this step";
    return in;
  }
  in.title = measured_.label;
  in.disp_px = measured;
  in.note = measured_.disp_px.empty()            ? "no measurement (scene)"
            : snap_.step >= snap_.measured_steps ? "path edited: no measurement"
                                                 : "no measurement at this step";
  if (replay_.tracked_markers == 0) {  // an empty sample is said in words, not drawn as 0.00 px
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
  const bool real_frame = background != nullptr;
  if (background == nullptr) background = textures_->neutral_for(iw, ih);

  const int models = static_cast<int>(snap_.models.size());
  const int n = models + 1 + static_cast<int>(measured_.beside.size());
  const auto names = panel_names();
  const int enlarged = static_cast<int>(std::find(names.begin(), names.end(), enlarged_) - names.begin());
  if (enlarged == n) enlarged_.clear();
  const bool one = !enlarged_.empty();
  const float line = ImGui::GetTextLineHeightWithSpacing();
  const FieldGrid grid = field_grid(width, height);
  // Enlarged: as wide as fits the area at the image's aspect, centred.
  const float pw = one ? std::min(width, (height - line - 4 - grid.legend_h) * float(iw) / float(ih)) : grid.cell_w;
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  if (!one) draw_view_cell(origin.x + grid.left, origin.y, grid.cell_w, grid.cell_h - 4);
  std::vector<std::vector<Vec2>> residuals(n);  // measured - model, when the residual view is on
  shown_fields_.clear();
  int hovered = -1;
  ImVec2 hovered_at;
  bool first_shown = true;
  for (int i = 0; i < n; ++i) {
    FieldPanelInput in = panel_input(i, measured, residuals[i]);
    in.background = background;
    in.real_frame = real_frame;
    in.backdrop = backdrops_.of(names[i]);
    if (i != models || measured != nullptr) shown_fields_.emplace_back(in.title, in.disp_px);
    if (one && i != enlarged) continue;
    const int cell = i + 1;  // the grid's cell: the 3D view is cell 0
    const int row = cell / grid.cols, col = cell % grid.cols;
    const ImVec2 panel_top = one ? ImVec2(origin.x + (width - pw) / 2, origin.y)
                                 : ImVec2(origin.x + grid.left + static_cast<float>(col) * (grid.cell_w + kPad),
                                          origin.y + static_cast<float>(row) * (grid.cell_h + kPad));
    ImGui::SetCursorScreenPos(panel_top);
    ImGui::BeginGroup();
    in.highlight_marker = forced_hover_ >= 0 ? forced_hover_ : hovered_marker_;
    in.enlarged = one;
    ImGui::PushID(i);
    const FieldPanelResult r = draw_field_panel(in, display_.scale(), pw, options_.interactive);
    if (r.toggle_enlarge) enlarged_ = one ? std::string() : names[i];
    if (r.cycle_backdrop) backdrops_.cycle(names[i]);
    // The model panel last clicked (or enlarged) is the one the 3D view colours its markers by.
    if ((r.clicked || r.toggle_enlarge) && i < models) display_.set_marker_model(i);
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
  const float legend_y = one ? origin.y + line + 4 + pw * float(ih) / float(iw)
                             : origin.y + grid.rows * (grid.cell_h + kPad);
  ImGui::SetCursorScreenPos(ImVec2(origin.x + (one ? (width - pw) / 2 : grid.left), legend_y));
  draw_field_legend(display_.scale(), pw / float(iw), one ? pw : width - 2 * grid.left);
  if (hovered >= 0) draw_marker_tooltip(hovered, hovered_at);
}

// The 3D view in the grid's first cell, with its legend over it (what the markers' colours, the tracked
// points' colours and their lines mean).
void Workbench::draw_view_cell(float x, float y, float w, float h) {
  ImGui::SetCursorScreenPos(ImVec2(x, y));
  viewport_.update(snap_, display_.marker_model(), display_.scale().colour_max_px, display_.scale().map);
  regions_.push_back({"3D view", x, y, w, h});
  if (auto target = viewport_.draw(w, h, pose_.shown(snap_, viewport_.dragging()), options_.interactive)) {
    if (view_drag_gesture_ == 0) {  // the drag's first move
      if (snap_.step + 1 < snap_.num_steps) message_ = "path replaced by your drag; Ctrl+Z brings it back";
      view_drag_gesture_ = state_->new_gesture();
    }
    pose_.drag_to(*target, *state_, /*skip_same=*/true, {"drag of the indenter", view_drag_gesture_});
  }
  if (!viewport_.dragging()) view_drag_gesture_ = 0;
  draw_view_legend(ImVec2(x, y), w);
}

void Workbench::draw_view_legend(ImVec2 at, float width) {
  const std::string model = snap_.models.empty() ? std::string("-")
                                                 : display_name(snap_.models[display_.marker_model()].id);
  struct Item {
    ImU32 colour;
    std::string text;
    bool line;
    ImVec2 pos;
  };
  std::vector<Item> items = {{IM_COL32(230, 230, 120, 255), "markers: |d| of " + model + " (panel colours)", false, {}},
                             {IM_COL32(60, 200, 90, 255), "stick", false, {}},
                             {IM_COL32(240, 150, 40, 255), "slip", false, {}},
                             {IM_COL32(150, 150, 150, 255), "free (tracked points)", false, {}},
                             {IM_COL32(60, 120, 255, 255), "anchor (blue points)", false, {}},
                             {IM_COL32(89, 140, 255, 255), "line: a tracked point to its anchor", true, {}}};
  const float lh = ImGui::GetTextLineHeight();
  float x = 0, y = 0, right = 0;
  for (std::size_t k = 0; k < items.size(); ++k) {  // rows: the markers, the point states, the lines
    const float w = ImGui::CalcTextSize(items[k].text.c_str()).x + 14;
    if (k == 1 || k == 4 || (k > 0 && x + w > width - 12)) x = 0, y += lh + 2;
    items[k].pos = ImVec2(at.x + 6 + x, at.y + 4 + y);
    x += w + 10;
    right = std::max(right, x);
  }
  ImDrawList* dl = ImGui::GetWindowDrawList();
  dl->PushClipRect(at, ImVec2(at.x + width, at.y + y + lh + 12), true);
  dl->AddRectFilled(ImVec2(at.x + 2, at.y + 2), ImVec2(at.x + 6 + right, at.y + 6 + y + lh), IM_COL32(20, 20, 25, 170),
                    3.0f);
  for (const Item& it : items) {
    const float cy = it.pos.y + lh / 2;
    if (it.line)
      dl->AddLine(ImVec2(it.pos.x + 1, cy), ImVec2(it.pos.x + 10, cy), it.colour, 1.5f);
    else
      dl->AddCircleFilled(ImVec2(it.pos.x + 5, cy), 4.0f, it.colour);
    dl->AddText(ImVec2(it.pos.x + 14, it.pos.y), IM_COL32(240, 240, 240, 255), it.text.c_str());
  }
  dl->PopClipRect();
}

// Once a frame, before drawing: the sliders catch up with the snapshot, the automatic scale, and the work
// on worker threads (RMSE series, corrected fields, the export's end in the status bar).
void Workbench::update_background() {
  parameters_.catch_up(snap_, *state_);
  if (display_.auto_scale_enabled()) display_.auto_scale(measured_at_step(), snap_);
  rmse_.update(snap_, *state_, measured_);
  residual_.update_corrected(snap_, *state_, measured_.poses);
  export_.take_report(message_);
}

void Workbench::wait_for_background() const {
  rmse_.wait();
  residual_.wait();
}

bool Workbench::animating() const {
  // An enlarged panel hides the 3D view: its pending re-render waits for the view to come back.
  return state_ != nullptr && (snap_.playing || loading_.loading() || (enlarged_.empty() && viewport_.busy()) ||
                               state_->version() != snap_.version || state_->pending_edits() > 0 || export_.busy());
}

WorkbenchRequest Workbench::draw(double frame_ms) {
  WorkbenchRequest req;
  if (state_ == nullptr) return req;
  snap_ = state_->snapshot();
  update_background();
  if (options_.interactive && !question_.asking() && !loading_.loading()) apply_actions(req);

  const ImGuiViewport* vp = ImGui::GetMainViewport();
  const float W = vp->Size.x, H = vp->Size.y;
  const float line = ImGui::GetTextLineHeightWithSpacing();
  // As tall as the status text wrapped to the window's width (an error is read whole), at most four lines.
  const float status_text_h = ImGui::CalcTextSize(status_text(snap_, frame_ms, options_.show_timings, message_).c_str(),
                                                  nullptr, false, W - 2 * ImGui::GetStyle().WindowPadding.x)
                                  .y;
  const float status_h = std::min(status_text_h, 4 * ImGui::GetTextLineHeight()) + line + 8 -
                         ImGui::GetTextLineHeight();
  const float left_w = left_column_px(W, dragged_left_px_);
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

  draw_column_divider(vp->Pos.x + left_w, H - status_h);
  draw_help_overlay(&show_help_);
  question_.draw(req);
  loading_.draw();
  return req;
}

// A strip over the columns' boundary that drags it: the left column widens for its tables (residual analysis,
// the fit's result) and narrows for more field panels.
void Workbench::draw_column_divider(float x, float height) {
  constexpr float kGrip = 6;
  const ImGuiViewport* vp = ImGui::GetMainViewport();
  ImGui::SetNextWindowPos(ImVec2(x - kGrip / 2, vp->Pos.y));
  ImGui::SetNextWindowSize(ImVec2(kGrip, height));
  ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(0, 0));
  ImGui::Begin("##column_divider", nullptr, kFixed | ImGuiWindowFlags_NoBackground | ImGuiWindowFlags_NoScrollbar);
  ImGui::InvisibleButton("##divider", ImVec2(kGrip, height));
  if (ImGui::IsItemHovered() || ImGui::IsItemActive()) ImGui::SetMouseCursor(ImGuiMouseCursor_ResizeEW);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("drag to widen or narrow the controls");
  if (ImGui::IsItemActive()) dragged_left_px_ = ImGui::GetIO().MousePos.x - vp->Pos.x;
  ImGui::End();
  ImGui::PopStyleVar();
}

}  // namespace sb::ui
