#pragma once
// The Replay section: the dataset, sample or scene to open, play/pause, speed, steps and the timeline
// (replay_panel in panels.hpp draws it); its requests go to the sync point or, for opening, to the app.
#include "core/workbench/app_state.hpp"
#include "widgets/panels.hpp"
#include "widgets/workbench_request.hpp"

namespace sb::ui {

void replay_section(const AppSnapshot& snap, ReplayUi& ui, AppState& state, WorkbenchRequest& req);

}  // namespace sb::ui
