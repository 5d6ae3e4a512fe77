#include "core/workbench/timeline_plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace sb {

float TimelinePlot::x_of_step(double step) const {
  return left + static_cast<float>((step + 0.5) * width / std::max(1, num_steps));
}

float TimelinePlot::y_of_value(double rmse_px) const {
  const double f = std::clamp(rmse_px / y_max_px, 0.0, 1.0);
  return top + height - static_cast<float>(f * height);
}

int TimelinePlot::step_at(float x) const {
  const int n = std::max(1, num_steps);
  const int k = static_cast<int>(std::floor((x - left) / width * static_cast<float>(n)));
  return std::clamp(k, 0, n - 1);
}

double nice_tick_step(double span, int max_ticks) {
  const double raw = span / std::max(1, max_ticks);
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (const double m : {1.0, 2.0, 5.0, 10.0})
    if (m * p >= raw * (1 - 1e-9)) return m * p;
  return 10 * p;
}

double nice_axis_max(double v, int max_ticks) {
  if (!(v > 0) || !std::isfinite(v)) return 1.0;
  const double step = nice_tick_step(v, max_ticks);
  return std::ceil(v / step * (1 - 1e-12)) * step;
}

std::vector<TimelineTick> TimelinePlot::time_ticks(int max_ticks) const {
  std::vector<TimelineTick> ticks;
  const double t_end = (std::max(1, num_steps) - 1) * dt_s;
  if (!(t_end > 0)) return {{0.0, x_of_step(0)}};
  const double step = nice_tick_step(t_end, max_ticks);
  for (int i = 0; i * step <= t_end * (1 + 1e-9); ++i) ticks.push_back({i * step, x_of_step(i * step / dt_s)});
  return ticks;
}

std::vector<TimelineTick> TimelinePlot::rmse_ticks(int max_ticks) const {
  std::vector<TimelineTick> ticks;
  const double step = nice_tick_step(y_max_px, max_ticks);
  for (int i = 0; i * step <= y_max_px * (1 + 1e-9); ++i) ticks.push_back({i * step, y_of_value(i * step)});
  return ticks;
}

std::string timeline_csv(const std::vector<std::string>& names, const std::vector<std::vector<double>>& series,
                         double dt_s) {
  std::string out = "step,time_s";
  for (const auto& n : names) out += "," + n;
  out += "\n";
  std::size_t rows = 0;
  for (const auto& s : series) rows = std::max(rows, s.size());
  char buf[64];
  for (std::size_t k = 0; k < rows; ++k) {
    std::snprintf(buf, sizeof buf, "%zu,%.6g", k, static_cast<double>(k) * dt_s);
    out += buf;
    for (const auto& s : series) {
      out += ",";
      if (k < s.size() && std::isfinite(s[k])) {
        std::snprintf(buf, sizeof buf, "%.6g", s[k]);
        out += buf;
      }
    }
    out += "\n";
  }
  return out;
}

}  // namespace sb
