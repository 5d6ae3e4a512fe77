#pragma once
// The whole workbench window, drawn once per frame from an AppState snapshot: controls on the left
// (replay, indenter pose, display scale, per-model parameters), the 3D view top right, the four field
// panels (HydroShear | FOTS | TacSL | Measured) below it, and a status bar. `shearbench gui` and
// `shearbench render` both call draw(), so a headless render shows exactly what the GUI shows.
#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/workbench/app_state.hpp"
#include "core/workbench/field_export.hpp"
#include "core/calibration/fit_job.hpp"
#include "core/calibration/param_sets.hpp"
#include "core/loop/residual_view.hpp"
#include "core/calibration/rmse_series.hpp"
#include "widgets/field_panel.hpp"
#include "widgets/panels.hpp"
#include "widgets/viewport.hpp"

namespace sb::ui {

// Measured marker data of the replayed sample, frame by frame (frame k goes with step k).
struct MeasuredData {
  std::vector<std::vector<Vec2>> disp_px;   // per frame, per marker; NaN for a marker the tracker lost
  std::vector<std::string> frame_paths;     // per frame PNG; empty when the dataset has no frames
  std::vector<Pose> poses;                  // the sample's pose path X_EI (for RMSE over time)
  std::string label = "Measured";
};

// Error metrics of a simulated field against a measured one (supplied by the app: core/calibration/metrics.hpp).
using MetricsFn = std::function<std::optional<FieldMetrics>(const std::vector<Vec2>& sim,
                                                            const std::vector<Vec2>& measured)>;

struct WorkbenchOptions {
  bool show_timings = true;   // off in render tests: no timing text in the image
  bool interactive = true;
};

// What the workbench asks of the app (things it cannot do from a snapshot).
// A part of the window in window pixels (top-left origin), for one-panel screenshots.
struct ScreenRegion {
  std::string name;   // "3D view", a model's display name, "Measured"
  float x = 0, y = 0, w = 0, h = 0;
};

struct WorkbenchRequest {
  bool quit = false;
  bool screenshot = false;
  std::string screenshot_region;            // empty: the whole window; else a ScreenRegion name
  std::optional<int> open_sample;           // index into ReplayUi::samples
  std::optional<std::string> open_dataset;  // a dataset folder (its first sample)
  std::optional<std::string> param_set;     // start every model again from this parameter set
  std::optional<std::string> load_params;   // params.json path
  std::optional<std::string> save_params;
  std::optional<std::string> save_session;  // session file path
  std::optional<std::string> open_session;
  std::optional<std::string> load_residual;  // a residual JSON (shearbench residual --json)
  std::optional<std::string> export_fields;  // a folder: every model's field along the path, tsd/1 each
  std::optional<std::pair<int, std::string>> switch_model;   // (slot, model id): FOTS / TacSL variant
  std::optional<std::string> beside_hydroshear;   // a HydroShear variant in its own panel ("": remove it)
  // The button the user chose in the question asked with Workbench::ask (its id, the button's index).
  std::optional<std::pair<std::string, int>> answer;
};

// Where the right column's grid puts its cells (the 3D view first, then the field panels).
struct FieldGrid {
  int cols = 3, rows = 2;
  float cell_w = 0, cell_h = 0;   // a cell's width and height (title row, image, gap)
  float left = 0;                 // the grid's left margin (centred in the column)
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
  void set_camera(CameraPreset preset) { viewport_.set_camera(preset); }
  const AppSnapshot& last_snapshot() const { return snap_; }
  // True while anything on screen may change without input (play-back, a drag, physics catching up).
  bool animating() const;
  FieldScale& scale() { return scale_; }
  bool& auto_scale_enabled() { return auto_scale_; }
  // One field panel enlarged to the whole field area (its name as shown: "FOTS", "Measured"; "" for
  // all panels). The panel's button and a double-click toggle it; false when no panel has that name.
  bool set_enlarged(const std::string& panel);
  const std::string& enlarged() const { return enlarged_; }
  // Headless renders: show marker `index`'s tooltip (every model's (du, dv) and the measurement's) as
  // if the mouse were on it in the first panel shown; -1: none.
  void set_hover_marker(int index) { forced_hover_ = index; }
  // A modal question with buttons; the choice comes back once in WorkbenchRequest::answer.
  void ask(std::string id, std::string text, std::vector<std::string> buttons);
  bool asking() const { return !question_id_.empty(); }
  // Headless renders: blocks until background computations (RMSE series) are done, so a render is
  // deterministic.
  void wait_for_background() const;
  // The field export on its worker thread (core/workbench/field_export): the Export row shows its progress and a
  // Cancel button; the status bar says how it ended.
  void start_export(FieldExportRequest request);
  FieldExportStatus export_status() const { return export_job_.status(); }
  void wait_for_export() const { export_job_.wait(); }
  // Shown in the Session section ("unsaved changes"; a session never saved does not say "saved").
  void set_unsaved(bool unsaved) { unsaved_ = unsaved; }
  void set_saved_once(bool saved) { saved_once_ = saved; }
  // The session file: what the quit dialog saves to. Adopted only once a save or an open succeeded; the
  // field shows it again after a failed open (revert_session_path).
  void set_session_path(const std::string& path);
  void revert_session_path() { set_session_path(session_file_); }
  // A session opening on a worker ("" when done): a progress line over the window, input held meanwhile.
  void set_loading(std::string what);
  bool loading() const { return !loading_what_.empty(); }
  // The 3D view's camera, for the session file.
  std::optional<CameraView> camera_view() const { return viewport_.camera_view(); }
  void set_camera_view(const CameraView& view) { viewport_.set_camera_view(view); }
  // Drops the residual analysis (its dataset was replaced): its panels, switches and Apply go with it.
  void clear_residual();
  void set_data_root(std::string root) { data_root_ = std::move(root); }
  // The parameter set the models started from: named in the Parameters section (provenance as tooltip),
  // the value R resets a slider to.
  // The set the models started from, and the sensor of the open scene (a set fitted on another sensor is
  // named as such under the combo).
  void set_param_set(NamedParamSet set, const std::string& sensor_model) {
    param_set_mismatch_ = sensor_mismatch(set, sensor_model);
    param_set_ = std::move(set);
  }
  std::string session_path() const { return session_file_; }
  ReplayUi& replay_ui() { return replay_; }
  // Where the 3D view and each field panel were drawn in the last frame.
  const std::vector<ScreenRegion>& regions() const { return regions_; }
  // A residual analysis to show (Residual section): ranked candidates, and the field panels can show
  // the residual (measured - model) and the corrected model (base + selected effects).
  void set_residual(ResidualSummary summary);
  void set_residual_view(bool residual_fields, bool corrected_model);
  // Sets the analysed model's panel to the analysis' fitted base parameters (the fair reference for the
  // corrected model); false when that model is not shown.
  bool apply_residual_base_params();
  // The loaded analysis' file ("" when none) and the two switches, for the session file.
  std::string residual_file() const { return residual_ ? residual_->file : std::string(); }
  bool residual_fields_shown() const { return show_residual_fields_; }
  bool corrected_shown() const { return show_corrected_; }

 private:
  struct Textures;
  void apply_actions(WorkbenchRequest& req);
  void draw_controls(WorkbenchRequest& req);
  void draw_fields(float width, float height);
  FieldGrid field_grid(float width, float height) const;
  FieldPanelInput panel_input(int i, const std::vector<Vec2>* measured, std::vector<Vec2>& residual);
  void draw_view_cell(float x, float y, float w, float h);
  void draw_view_legend(ImVec2 at, float width);
  void draw_marker_tooltip(int marker, ImVec2 at);
  std::vector<std::string> panel_names() const;
  void draw_question(WorkbenchRequest& req);
  void update_rmse_series();
  void draw_fit_panel();
  void draw_loss_plot(const std::vector<float>& losses);
  void draw_param_set_row(WorkbenchRequest& req);
  std::string param_set_label(const std::string& name);
  void draw_residual_panel(WorkbenchRequest& req);
  void draw_contact_frame_tables(const ResidualSummary& r);
  void draw_variant_switches(WorkbenchRequest& req);
  void draw_export_row(WorkbenchRequest& req);
  void report_export();
  void update_corrected_series();
  int corrected_slot() const;   // the model panel the residual analysis belongs to (-1: none shown)
  const std::vector<Vec2>* corrected_at_step();
  void draw_rmse_plots();
  void auto_scale();
  void nudge(const Pose& delta_E, bool rotate_about_origin);
  const std::vector<Vec2>* measured_at_step() const;

  WorkbenchOptions options_;
  AppState* state_ = nullptr;
  MeasuredData measured_;
  std::string title_;
  ReplayUi replay_;
  MetricsFn metrics_;
  Viewport3D viewport_;
  std::unique_ptr<Textures> textures_;
  AppSnapshot snap_;
  FieldScale scale_;
  bool auto_scale_ = true;
  bool hold_scale_ = true;        // the auto scale only grows (colours keep their meaning)
  double held_max_px_ = 0;        // the largest reference |d| seen since the session opened
  double sample_max_px_ = 0;      // the replayed sample's largest measured |d| (0: a scene)
  double marker_pitch_px_ = 33.0;
  int marker_model_ = 0;
  std::string enlarged_;           // the enlarged field panel's name, "" for none
  int hovered_marker_ = -1;        // the marker under the mouse in the last frame (ringed in every panel)
  int forced_hover_ = -1;
  // What the field panels drew in this frame (title, field or null), for the marker tooltip.
  std::vector<std::pair<std::string, const std::vector<Vec2>*>> shown_fields_;
  bool show_help_ = false;
  std::vector<ParamSet> edit_params_;
  std::optional<Pose> last_drag_;
  char params_path_[512] = "params.json";
  char session_path_[512] = "";   // the Session field (what Save writes to)
  std::string session_file_;       // the adopted session file (set_session_path)
  bool unsaved_ = false;
  bool saved_once_ = false;
  std::string loading_what_;
  std::chrono::steady_clock::time_point loading_since_;
  void draw_loading();
  void draw_session_section(WorkbenchRequest& req);
  void draw_display_section(WorkbenchRequest& req);
  RmseSeriesJob rmse_job_;
  FitJob fit_job_;
  std::string data_root_;
  char fit_dataset_[512] = "";
  int fit_model_ = 0;
  NamedParamSet param_set_ = published_param_set();
  std::string param_set_mismatch_;   // sensor_mismatch() of the set and the open scene
  std::map<std::string, std::string> param_set_labels_;   // set name -> its combo label
  bool show_published_ = false;
  bool fit_joint_ = true;    // stages then joint: the best fit; off = the paper's stages only
  int fit_iterations_ = 30;
  std::string fit_model_id_;          // the model the shown result belongs to
  ParamSet fit_start_params_;         // what that fit started from
  bool fit_result_handled_ = false;   // applied or discarded
  std::vector<std::vector<double>> rmse_params_;   // the parameter values the running/last job used
  std::vector<ScreenRegion> regions_;
  int screenshot_region_ = 0;   // 0: window, i: regions_[i - 1]
  char export_path_[512] = "fields_export";
  FieldExportJob export_job_;
  bool export_reported_ = true;   // the last export's end is in the status bar
  std::optional<ResidualSummary> residual_;
  char residual_path_[512] = "residual.json";
  bool show_residual_fields_ = false;
  int contact_table_ = 0;   // the contact-frame table shown in the Residual section
  bool show_corrected_ = true;
  FieldSeriesJob corrected_job_;
  bool corrected_started_ = false;
  bool open_residual_section_ = false;   // a new analysis opens its section once
  std::string question_id_, question_text_;
  std::vector<std::string> question_buttons_;
  std::string message_;
};

}  // namespace sb::ui
