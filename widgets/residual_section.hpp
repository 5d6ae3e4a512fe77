#pragma once
// The Residual section of the workbench: a residual analysis (shearbench residual --json) read back, its
// ranked candidates, and the field panels switched to the residual (measured - model) and to the corrected
// model: the loop's answer, the selected model form (else the base) with the selected effects, at their
// fitted parameters, computed along the measured sample's poses on a worker thread.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/loop/residual_view.hpp"
#include "core/workbench/app_state.hpp"
#include "widgets/workbench_request.hpp"

namespace sb::ui {

class ResidualSection {
 public:
  // A residual analysis to show; its section opens once. `data_root` shortens the path shown.
  void set(ResidualSummary summary, const std::string& data_root);
  // Drops the analysis (its dataset was replaced): its panels, switches and Apply go with it.
  void clear();
  // The corrected fields are computed afresh (a new sample).
  void restart_corrected();
  void set_view(bool residual_fields, bool corrected_model) {
    show_residual_fields_ = residual_fields;
    show_corrected_ = corrected_model;
  }
  // The loaded analysis' file ("" when none) and the two switches, for the session file.
  std::string file() const { return residual_ ? residual_->file : std::string(); }
  bool residual_fields_shown() const { return show_residual_fields_; }
  bool corrected_shown() const { return show_corrected_; }
  // True once after an analysis was set: the section's header opens.
  bool take_open_request() { return std::exchange(open_section_, false); }

  // Sets the analysed model's panel to the analysis' fitted base parameters (the fair reference for the
  // corrected model); false when that model is not shown.
  bool apply_base_params(const AppSnapshot& snap, AppState& state) const;
  // The model panel the analysis belongs to (-1: none shown, or nothing selected).
  int corrected_slot(const AppSnapshot& snap) const;
  // Starts the corrected model's fields along the measured poses, once per analysis and sample.
  void update_corrected(const AppSnapshot& snap, const AppState& state, const std::vector<Pose>& poses);
  // The corrected model's field at the snapshot's step (null while computing or out of range); a failed
  // worker is said once in `message` and the corrected view switched off.
  const std::vector<Vec2>* corrected_at_step(const AppSnapshot& snap, std::string& message);
  // The corrected model's field at every step (null while computing or not shown); a failed worker as above.
  const std::vector<std::vector<Vec2>>* corrected_series(std::string& message);
  const std::string& corrected_title() const { return residual_->after_model; }
  bool correcting() const { return corrected_job_.running(); }
  void wait() const { corrected_job_.wait(); }

  void draw(const AppSnapshot& snap, AppState& state, bool have_poses, std::string& message, WorkbenchRequest& req);

 private:
  void draw_summary(const ResidualSummary& r) const;
  void draw_evidence(const ResidualSummary& r) const;
  void draw_candidates(const ResidualSummary& r) const;
  void draw_contact_frame_tables(const ResidualSummary& r);
  void draw_input_response_table(const ResidualSummary& r);
  static void draw_binned_means_table(const ResidualSummary& r);
  void draw_switches(const AppSnapshot& snap, AppState& state, bool have_poses, std::string& message);

  std::optional<ResidualSummary> residual_;
  std::string path_ = "residual.json";
  bool show_residual_fields_ = false;
  int contact_table_ = 0;  // the contact-frame table shown
  bool show_corrected_ = true;
  FieldSeriesJob corrected_job_;
  bool corrected_started_ = false;
  bool open_section_ = false;  // a new analysis opens its section once
};

}  // namespace sb::ui
