#include "widgets/replay_section.hpp"

namespace sb::ui {

void replay_section(const AppSnapshot& snap, ReplayUi& ui, AppState& state, WorkbenchRequest& req) {
  const ReplayRequest r = replay_panel(snap, ui);
  if (r.toggle_play) {
    // Play at the end starts again from the beginning.
    if (!snap.playing && snap.step >= snap.num_steps - 1) state.request_seek(-1);
    state.set_playing(!snap.playing);
  }
  if (r.seek_to != -2) state.request_seek(r.seek_to);
  if (r.speed > 0) state.set_speed(r.speed);
  if (r.open_sample) req.open_sample = ui.sample_index;
  if (r.open_dataset) req.open_dataset = ui.dataset_input;
}

}  // namespace sb::ui
