#pragma once
// What the GUI and the headless render open: a scene file (trajectory or dataset sample) turned into an
// AppState with its three models, plus the measured data of a replayed sample. Shared by cmd_gui and
// cmd_render so both show the same thing.
#include <memory>
#include <string>

#include "core/app_state.hpp"
#include "core/scene.hpp"
#include "widgets/workbench.hpp"

namespace sb::app {

struct SessionOptions {
  std::string scene_path;     // empty: scenes/default.json, else a built-in sphere press-and-slide
  std::string dataset_dir;    // replay a tsd/1 dataset instead of a scene
  std::string sample_id;      // empty: the dataset's first sample
  std::string data_root;
  std::string fots_id = "fots";     // or fots-reimpl
  std::string tacsl_id = "tacsl";   // or tacsl-normalized
  std::string indenter_mesh;        // replaces the scene's indenter by this mesh ("data:meshes/cow.obj")
  double indenter_scale = 0.002;    // file units to metres for indenter_mesh
};

struct Session {
  Scene scene;
  std::unique_ptr<AppState> state;
  ui::MeasuredData measured;
  ui::ReplayUi replay;
  std::string title;
};

Session open_session(const SessionOptions& options);
// The path of scenes/default.json (working directory first, then the source tree); empty when absent.
std::string default_scene_path();
// The built-in default: a 4 mm sphere pressed 1 mm into the flat pad, then slid 3 mm along +x.
Scene builtin_default_scene();
// Error metrics for the field panels (core/metrics.hpp).
ui::MetricsFn field_metrics();

// params.json: {"hydroshear": {"mu": 0.5, ...}, "fots": {...}}; load queues the tables on the state.
void load_params_file(AppState& state, const std::string& path);
void save_params_file(const AppSnapshot& snap, const std::string& path);

// "1600x900" -> (1600, 900); throws InputError.
std::pair<int, int> parse_size(const std::string& text);

}  // namespace sb::app
