#include "core/workbench/double_click.hpp"

#include <cmath>

namespace sb {

void DoubleClickDetector::begin_poll(double busy_s) {
  busy_s_ = busy_s > 0 ? busy_s : 0.0;
  double_clicked_ = false;
}

void DoubleClickDetector::press(double t_s, double x_px, double y_px) {
  const bool close_in_time = t_s - busy_s_ - first_t_s_ <= kMaxGapS;
  const bool close_in_space = std::hypot(x_px - first_x_, y_px - first_y_) <= kMaxMovePx;
  if (has_first_ && close_in_time && close_in_space) {
    double_clicked_ = true;
    has_first_ = false;  // a third press starts the next double-click
    return;
  }
  has_first_ = true;
  first_t_s_ = t_s;
  first_x_ = x_px;
  first_y_ = y_px;
}

}  // namespace sb
