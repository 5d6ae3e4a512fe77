#pragma once
// The Fit section: calibration on a worker thread (core/calibration/fit_job.hpp) that the section polls each
// frame; its progress, loss plot and result table, and Apply (the fitted values go to the model at the sync
// point) or Discard.
#include <string>
#include <vector>

#include "core/calibration/fit_job.hpp"
#include "core/workbench/app_state.hpp"

namespace sb::ui {

class FitSection {
 public:
  void set_data_root(std::string root) { data_root_ = std::move(root); }
  // `replayed_dataset` fills the dataset field while it is empty.
  void draw(const AppSnapshot& snap, AppState& state, const std::string& replayed_dataset);

 private:
  void draw_settings(const AppSnapshot& snap);
  void draw_run_row(const AppSnapshot& snap, const FitJobStatus& st);
  void start(const AppSnapshot& snap);
  void draw_result(const AppSnapshot& snap, AppState& state, const FitJobStatus& st);
  static void draw_loss_plot(const std::vector<StageLosses>& stages);
  static void draw_loss_tooltip(const std::vector<StageLosses>& stages);

  FitJob job_;
  std::string data_root_;
  std::string dataset_;
  int model_ = 0;
  bool joint_ = true;  // stages then joint: the best fit; off = the paper's stages only
  int iterations_ = 30;
  std::string model_id_;         // the model the shown result belongs to
  ParamSet start_params_;        // what that fit started from
  bool result_handled_ = false;  // applied or discarded
};

}  // namespace sb::ui
