#pragma once
// What the GUI and the headless render open: a scene file (trajectory or dataset sample) turned into an
// AppState with its three models, plus the measured data of a replayed sample. Shared by cmd_gui and
// cmd_render so both show the same thing.
#include <CLI/CLI.hpp>
#include <memory>
#include <string>
#include <vector>

#include "core/calibration/param_sets.hpp"
#include "core/data/scene.hpp"
#include "core/workbench/app_state.hpp"
#include "core/workbench/session_file.hpp"
#include "widgets/workbench.hpp"

namespace sb::app {

struct SessionOptions {
  SessionSource open;  // what to open (the session file's "open" section)
  std::string data_root;
};

// The flags that say what to open (--scene, --dataset, --sample, --indenter-mesh, --indenter-scale,
// --fots, --tacsl), shared by gui and render, and the same flags back as arguments (gui's headless re-run).
void add_source_options(CLI::App& sub, SessionSource& open);
std::vector<std::string> source_arguments(const SessionSource& open);

// `--residual R` without --dataset or --scene: R's own dataset (the report's JSON names it) when the data root
// has it (core/workbench/report_dataset); `open` unchanged otherwise.
void open_report_dataset(SessionSource& open, const std::string& residual_file, const std::string& data_root_flag);

struct Session {
  Scene scene;
  NamedParamSet param_set;  // what the models started from (before the scene's own tables)
  std::unique_ptr<AppState> state;
  ui::MeasuredData measured;
  ui::ReplayUi replay;
  std::string title;
  std::string loop_answer_model;  // the loop's answer for a real recording's sensor (core/loop/loop_answer.hpp)
  std::string beside_note;        // why the panel beside HydroShear shows what it shows, when the session chose it
};

Session open_session(const SessionOptions& options);
// The path of scenes/default.json in shearbench's home (base/install_paths.hpp); empty when absent.
std::string default_scene_path();
// The built-in default: a 4 mm sphere pressed 1 mm into the flat pad, then slid 3 mm along +x.
Scene builtin_default_scene();
// Error metrics for the field panels (core/calibration/metrics.hpp).
ui::MetricsFn field_metrics();

// params.json: {"hydroshear": {"mu": 0.5, ...}, "fots": {...}}; load queues the tables on the state.
void load_params_file(AppState& state, const std::string& path);
void save_params_file(const AppSnapshot& snap, const std::string& path);

// "1600x900" -> (1600, 900); throws InputError.
std::pair<int, int> parse_size(const std::string& text);

}  // namespace sb::app
