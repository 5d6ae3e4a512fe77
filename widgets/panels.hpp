#pragma once
// The workbench's control panels. Each is a function that draws into the current ImGui window and
// returns whether the user changed something (and what, through its arguments).
#include <imgui.h>

#include <string>
#include <vector>

#include "core/base/params.hpp"
#include "core/workbench/app_state.hpp"

namespace sb::ui {

// One slider per ParamSpec (unit in the format, logarithmic where spec.log_scale, hover for help) and
// a reset-to-default button. Returns true when a value changed.
// Sliders of one model's parameters. R resets a slider to `reference` (the active parameter set's value);
// with `published`, each row also shows the authors' value.
// Each slider's tooltip gives its range and unit; a value at a bound is marked "at bound"; a value typed out of
// range is set to its bound and `notes` (one per parameter, kept by the caller across frames) says so under it.
bool param_panel(const std::string& model_id, ParamSet& params, const ParamSet& reference,
                 const ParamSet* published = nullptr, std::vector<std::string>* notes = nullptr);

// The orange of "at bound" and of a note on a value set to its bound.
inline const ImVec4 kAtBoundColour{1.0f, 0.65f, 0.2f, 1.0f};
// "at bound" beside the last item, its range as the tooltip.
void at_bound_mark(const ParamSpec& spec);
// A note under a field (a typed value set to its bound).
void note_line(const std::string& note);

// Numeric entry of the indenter pose: position in mm and roll-pitch-yaw (extrinsic xyz) in degrees.
bool pose_panel(Pose& X_EI);
Vec3 rpy_deg_of(const Mat3& R);
Mat3 rotation_from_rpy_deg(const Vec3& rpy_deg);

struct ReplayRequest {
  bool toggle_play = false;
  int seek_to = -2;           // -2: none
  double speed = -1;          // < 0: unchanged
  bool open_sample = false;   // open samples[sample_index] of dataset_dir
  bool open_dataset = false;  // open the folder typed in dataset_input (its first sample)
};

// Dataset/sample chooser (the caller lists the samples), play/pause, speed, step buttons and a timeline.
struct ReplayUi {
  std::string dataset_dir;
  std::vector<std::string> samples;
  int sample_index = 0;
  std::string dataset_input;         // the Open field: what is typed or chosen
  std::vector<std::string> choices;  // the Open list: recent opens, scenes/*.json, the data root's datasets
  int tracked_markers = -1;          // markers tracked in the sample's last frame (-1: not a dataset)
  int total_markers = 0;
};
ReplayRequest replay_panel(const AppSnapshot& snap, ReplayUi& ui);

// "HydroShear 3.1 ms | FOTS 0.2 ms | ..." plus frame time; without timings (tests) only the step.
// The message first (errors are read, timings glanced at), wrapped to the bar's width: nothing is cut at the
// window's edge. status_text is what it draws; the workbench sizes the bar from it.
std::string status_text(const AppSnapshot& snap, double frame_ms, bool show_timings, const std::string& message);
void status_bar(const AppSnapshot& snap, double frame_ms, bool show_timings, const std::string& message);

// Pretty model names for the panels.
std::string display_name(const std::string& model_id);
// `text` cut with ".." to fit `max_width` pixels in the current font (unchanged when it fits).
std::string elide(const std::string& text, float max_width);

// A tooltip whose text wraps at about 60 characters (the residual loop's reasons run to several hundred).
void wrapped_tooltip(const std::string& text);

}  // namespace sb::ui
