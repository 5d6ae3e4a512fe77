#pragma once
// What the workbench's sections ask of the app (things they cannot do from a snapshot), and the parts of
// the window they name for screenshots.
#include <optional>
#include <string>
#include <utility>

namespace sb::ui {

// A part of the window in window pixels (top-left origin), for one-panel screenshots.
struct ScreenRegion {
  std::string name;  // "3D view", a model's display name, "Measured"
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
  std::optional<std::string> load_residual;                 // a residual JSON (shearbench residual --json)
  std::optional<std::string> export_fields;                 // a folder: every model's field along the path, tsd/1 each
  std::optional<std::pair<int, std::string>> switch_model;  // (slot, model id): FOTS / TacSL variant
  std::optional<std::string> beside_hydroshear;             // a HydroShear variant in its own panel ("": remove it)
  bool undo_open = false;  // bring back the unsaved work the last open replaced (Ctrl+Z with nothing else to undo)
  // The button the user chose in the question asked with Workbench::ask (its id, the button's index).
  std::optional<std::pair<std::string, int>> answer;
};

}  // namespace sb::ui
