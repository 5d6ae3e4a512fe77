#pragma once
// The RMSE timeline's geometry, without a window: one plot of every model's RMSE (px) against the replay's
// steps, its axes' ticks, where a value is drawn and which step a pointer x seeks to; and the plot's CSV.
// The ImGui drawing is widgets/rmse_section.
#include <string>
#include <vector>

namespace sb {

// A tick on an axis: its value and where it is drawn (screen px).
struct TimelineTick {
  double value = 0;
  float px = 0;
};

// The plot area in screen pixels (y grows down) for `num_steps` steps of `dt_s` each and RMSE in [0, y_max_px].
// Step k is drawn at the middle of its column: x = left + (k + 0.5) * width / num_steps.
struct TimelinePlot {
  float left = 0, top = 0, width = 1, height = 1;
  int num_steps = 1;    // >= 1
  double dt_s = 0.02;   // time of step k: k * dt_s (as the Replay section's "t = ")
  double y_max_px = 1;  // > 0: the top edge's RMSE

  float x_of_step(double step) const;
  // Clamped into the plot: a value over the top is drawn at the top edge, a negative one at the bottom.
  float y_of_value(double rmse_px) const;
  // The step whose column holds screen x, clamped into [0, num_steps - 1] (a drag past an edge seeks to it).
  int step_at(float x) const;
  // Ticks on the time axis (seconds, 1-2-5 steps, at most `max_ticks`) and on the RMSE axis (px, from 0).
  std::vector<TimelineTick> time_ticks(int max_ticks) const;
  std::vector<TimelineTick> rmse_ticks(int max_ticks) const;
};

// The smallest 1, 2 or 5 times a power of ten that is >= span / max_ticks (the step between ticks); span > 0.
double nice_tick_step(double span, int max_ticks);
// The top of the RMSE axis for a largest finite value `v`: the next multiple of its tick step (1 when v <= 0).
double nice_axis_max(double v, int max_ticks);

// The plot as CSV: "step,time_s,<name>..." then one row per step; a frame that does not count (NaN: nothing
// measured moves) is an empty cell. Every series has num_steps values or fewer (missing ones empty too).
std::string timeline_csv(const std::vector<std::string>& names, const std::vector<std::vector<double>>& series,
                         double dt_s);

}  // namespace sb
