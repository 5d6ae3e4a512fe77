#pragma once
// The whole workbench window, drawn once per frame from an AppState snapshot: controls on the left
// (replay, indenter pose, display scale, per-model parameters), the 3D view top right, the four field
// panels (HydroShear | FOTS | TacSL | Measured) below it, and a status bar. `shearbench gui` and
// `shearbench render` both call draw(), so a headless render shows exactly what the GUI shows.
//
// The controls are sections (docs/architecture.md, "The Workbench by section"): each owns its state and
// draws itself (replay_section, pose_section, display_section, export_row, parameters_section, rmse_section,
// residual_section, fit_section, session_section, dialogs). The Workbench holds them, takes the snapshot
// once per frame, and is the one place where they meet the app (WorkbenchRequest) and the sync point
// (AppState).
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/calibration/param_sets.hpp"
#include "core/loop/residual_view.hpp"
#include "core/workbench/app_state.hpp"
#include "core/workbench/field_export.hpp"
#include "core/workbench/session_file.hpp"
#include "widgets/dialogs.hpp"
#include "widgets/display_section.hpp"
#include "widgets/export_row.hpp"
#include "widgets/field_panel.hpp"
#include "widgets/fit_section.hpp"
#include "widgets/keys.hpp"
#include "widgets/measured_data.hpp"
#include "widgets/panels.hpp"
#include "widgets/parameters_section.hpp"
#include "widgets/pose_section.hpp"
#include "widgets/residual_section.hpp"
#include "widgets/rmse_section.hpp"
#include "widgets/session_section.hpp"
#include "widgets/viewport.hpp"
#include "widgets/workbench_request.hpp"

namespace sb::ui {

// Error metrics of a simulated field against a measured one (supplied by the app: core/calibration/metrics.hpp).
using MetricsFn =
    std::function<std::optional<FieldMetrics>(const std::vector<Vec2>& sim, const std::vector<Vec2>& measured)>;

struct WorkbenchOptions {
  bool show_timings = true;  // off in render tests: no timing text in the image
  bool interactive = true;
};

// Where the right column's grid puts its cells (the 3D view first, then the field panels).
struct FieldGrid {
  int cols = 3, rows = 2;
  float cell_w = 0, cell_h = 0;  // a cell's width and height (title row, image, gap)
  float left = 0;                // the grid's left margin (centred in the column)
  float legend_h = 0;            // the shared legend under the grid (field_legend_height, once a frame)
};

class Workbench {
 public:
  explicit Workbench(WorkbenchOptions options);
  ~Workbench();

  // A new session (scene or sample). `state` must outlive the next set_session / the workbench.
  void set_session(AppState* state, MeasuredData measured, std::string title, ReplayUi replay);
  void set_metrics(MetricsFn fn) { metrics_ = std::move(fn); }
  // Draws one frame of windows (between GlWindow::begin_frame and render).
  WorkbenchRequest draw(double frame_ms);
  void set_message(std::string m) { message_ = std::move(m); }
  const std::string& message() const { return message_; }
  void set_camera(CameraPreset preset) { viewport_.set_camera(preset); }
  const AppSnapshot& last_snapshot() const { return snap_; }
  // True while anything on screen may change without input (play-back, a drag, physics catching up).
  bool animating() const;
  FieldScale& scale() { return display_.scale(); }
  bool& auto_scale_enabled() { return display_.auto_scale_enabled(); }
  // One field panel enlarged to the whole field area (its name as shown: "FOTS", "Measured"; "" for
  // all panels). The panel's button and a double-click toggle it; false when no panel has that name.
  bool set_enlarged(const std::string& panel);
  const std::string& enlarged() const { return enlarged_; }
  // Headless renders: show marker `index`'s tooltip (every model's (du, dv) and the measurement's) as
  // if the mouse were on it in the first panel shown; -1: none.
  void set_hover_marker(int index) { forced_hover_ = index; }
  // A modal question with buttons; the choice comes back once in WorkbenchRequest::answer.
  void ask(std::string id, std::string text, std::vector<std::string> buttons) {
    question_.ask(std::move(id), std::move(text), std::move(buttons));
  }
  bool asking() const { return question_.asking(); }
  // Headless renders: blocks until background computations (RMSE series) are done, so a render is
  // deterministic.
  void wait_for_background() const;
  // The field export on its worker thread (core/workbench/field_export): the Export row shows its progress and a
  // Cancel button; the status bar says how it ended.
  void start_export(FieldExportRequest request) { export_.start(std::move(request)); }
  FieldExportStatus export_status() const { return export_.status(); }
  void wait_for_export() const { export_.wait(); }
  // Shown in the Session section ("unsaved changes"; a session never saved does not say "saved").
  void set_unsaved(bool unsaved) { session_.set_unsaved(unsaved); }
  void set_saved_once(bool saved) { session_.set_saved_once(saved); }
  // The session file: what the quit dialog saves to. Adopted only once a save or an open succeeded; the
  // field shows it again after a failed open (revert_session_path).
  void set_session_path(const std::string& path) { session_.set_file(path); }
  // What Ctrl+Z does once the session has no edit left to undo: bring back the unsaved work an open replaced
  // ("": nothing to bring back). Named on the Undo button.
  void set_open_undo(std::string what) { open_undo_ = std::move(what); }
  void revert_session_path() { session_.revert(); }
  // A session opening on a worker ("" when done): a progress line over the window, input held meanwhile.
  void set_loading(std::string what) { loading_.set(std::move(what)); }
  bool loading() const { return loading_.loading(); }
  // The 3D view's camera, for the session file.
  std::optional<CameraView> camera_view() const { return viewport_.camera_view(); }
  void set_camera_view(const CameraView& view) { viewport_.set_camera_view(view); }
  // What a session file keeps of the display besides the camera and scale: the 3D markers' model (by id), the
  // colour map and each panel's frame backdrop (core/workbench/session_file.hpp).
  void write_display_choices(SessionFile& f) const;
  void read_display_choices(const SessionFile& f);
  // Drops the residual analysis (its dataset was replaced): its panels, switches and Apply go with it.
  void clear_residual() { residual_.clear(); }
  void set_data_root(std::string root) {
    data_root_ = root;
    fit_.set_data_root(std::move(root));
  }
  // The parameter set the models started from: named in the Parameters section (provenance as tooltip),
  // the value R resets a slider to.
  // The set the models started from, and the sensor of the open scene (a set fitted on another sensor is
  // named as such under the combo), and the loop's answer for that sensor ("" when it has none) the combo beside
  // HydroShear offers.
  void set_param_set(NamedParamSet set, const std::string& sensor_model, const std::string& loop_answer_model = "") {
    parameters_.set_param_set(std::move(set), sensor_model, loop_answer_model);
  }
  std::string session_path() const { return session_.file(); }
  void set_output_folder(const std::string& folder) { session_.set_output_folder(folder); }
  ReplayUi& replay_ui() { return replay_; }
  // Where the 3D view and each field panel were drawn in the last frame.
  const std::vector<ScreenRegion>& regions() const { return regions_; }
  // A residual analysis to show (Residual section): ranked candidates, and the field panels can show
  // the residual (measured - model) and the corrected model (base + selected effects).
  void set_residual(ResidualSummary summary) { residual_.set(std::move(summary), data_root_); }
  void set_residual_view(bool residual_fields, bool corrected_model) {
    residual_.set_view(residual_fields, corrected_model);
  }
  // Sets the analysed model's panel to the analysis' fitted base parameters (the fair reference for the
  // corrected model); false when that model is not shown.
  bool apply_residual_base_params() { return residual_.apply_base_params(snap_, *state_); }
  // The loaded analysis' file ("" when none) and the two switches, for the session file.
  std::string residual_file() const { return residual_.file(); }
  bool residual_fields_shown() const { return residual_.residual_fields_shown(); }
  bool corrected_shown() const { return residual_.corrected_shown(); }

 private:
  struct Textures;
  void apply_actions(WorkbenchRequest& req);
  void apply_action(Action action, WorkbenchRequest& req);
  void update_background();
  void draw_controls(WorkbenchRequest& req);
  RmseRowOverride corrected_rmse_row();
  std::string rmse_csv_path() const;
  void draw_fields(float width, float height);
  void draw_column_divider(float x, float height);
  FieldGrid field_grid(float width, float height) const;
  FieldPanelInput panel_input(int i, const std::vector<Vec2>* measured, std::vector<Vec2>& residual);
  void model_panel_input(int i, const std::vector<Vec2>* measured, std::vector<Vec2>& residual, FieldPanelInput& in);
  void draw_view_cell(float x, float y, float w, float h);
  void draw_view_legend(ImVec2 at, float width);
  void draw_marker_tooltip(int marker, ImVec2 at);
  std::vector<std::string> panel_names() const;
  const std::vector<Vec2>* measured_at_step() const;

  WorkbenchOptions options_;
  AppState* state_ = nullptr;
  MeasuredData measured_;
  std::string title_;
  ReplayUi replay_;
  MetricsFn metrics_;
  Viewport3D viewport_;
  std::unique_ptr<Textures> textures_;
  AppSnapshot snap_;  // taken once per frame: every section draws from it
  std::string data_root_;
  std::string message_;  // the status bar's message
  // The sections, in the order the control column shows them.
  PoseSection pose_;
  DisplaySection display_;
  ExportRow export_;
  ParametersSection parameters_;
  RmseSection rmse_;
  ResidualSection residual_;
  FitSection fit_;
  SessionSection session_;
  QuestionDialog question_;
  LoadingDialog loading_;
  bool show_help_ = false;
  float dragged_left_px_ = 0;            // where the user dragged the columns' divider (0: never)
  std::uint64_t view_drag_gesture_ = 0;  // the 3D view's drag in progress (0: none): one undo entry
  void say_if_path_replaced(const char* by);
  void draw_undo_row(WorkbenchRequest& req);
  void undo(WorkbenchRequest& req);
  std::string open_undo_;  // what undoing the last open does ("": nothing to bring back)
  // The field area (the right column).
  std::string enlarged_;      // the enlarged field panel's name, "" for none
  PanelBackdrops backdrops_;  // each panel's choice of how a recorded frame sits under its arrows
  int hovered_marker_ = -1;   // the marker under the mouse in the last frame (ringed in every panel)
  int forced_hover_ = -1;
  // What the field panels drew in this frame (title, field or null), for the marker tooltip.
  std::vector<std::pair<std::string, const std::vector<Vec2>*>> shown_fields_;
  std::vector<ScreenRegion> regions_;
};

}  // namespace sb::ui
