#pragma once
// The Parameters section: the model variants shown (HydroShear, FOTS, TacSL families, and a HydroShear variant
// beside HydroShear), a params.json to load or save, the parameter set every model started from, and each
// model's sliders. Slider edits go to a local copy per model that is sent whole to the sync point.
#include <map>
#include <string>
#include <vector>

#include "core/calibration/param_sets.hpp"
#include "core/workbench/app_state.hpp"
#include "widgets/workbench_request.hpp"

namespace sb::ui {

class ParametersSection {
 public:
  // The set the models started from (named in the section, provenance as tooltip, the value R resets a
  // slider to), the sensor of the open scene (a set fitted on another sensor is named as such), and the loop's
  // answer for that sensor, offered beside HydroShear ("" when it has none).
  void set_param_set(NamedParamSet set, const std::string& sensor_model, const std::string& loop_answer_model) {
    mismatch_ = sensor_mismatch(set, sensor_model);
    set_ = std::move(set);
    loop_answer_ = loop_answer_model;
  }
  // A new session: the sliders start from its models' parameters.
  void start_session(const AppSnapshot& snap);
  // Parameters changed elsewhere (loaded from a file) show up in the sliders, unless one is being dragged or
  // an edit is still on its way.
  void catch_up(const AppSnapshot& snap, const AppState& state);
  void draw(const AppSnapshot& snap, AppState& state, WorkbenchRequest& req);

 private:
  void draw_variant_switches(const AppSnapshot& snap, WorkbenchRequest& req);
  void draw_file_row(WorkbenchRequest& req);
  void draw_param_set_row(WorkbenchRequest& req);
  void draw_sliders(const AppSnapshot& snap, AppState& state);
  std::string param_set_label(const std::string& name);

  std::string file_ = "params.json";
  std::vector<ParamSet> edit_params_;
  std::vector<std::vector<std::string>> notes_;  // per model, per parameter: a typed value set to its bound
  NamedParamSet set_ = published_param_set();
  std::string mismatch_;                       // sensor_mismatch() of the set and the open scene
  std::string loop_answer_;                    // the loop's answer for the open recording's sensor, or ""
  std::map<std::string, std::string> labels_;  // set name -> its combo label
  bool show_published_ = false;
  std::uint64_t slider_gesture_ = 0;  // the slider drag in progress (0: none)
};

}  // namespace sb::ui
