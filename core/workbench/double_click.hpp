#pragma once
// Double-clicks from the window's mouse events rather than from ImGui's frame clock. ImGui 1.86 sees a
// press only as "down at NewFrame" and times a double-click between frames with a 0.30 s window, so on a
// slow frame (llvmpipe under load draws one in 150-500 ms) two quick presses were not a double-click, and
// two presses polled in one frame counted as one. Here every press is recorded when it is polled, with
// the number of the event poll that delivered it: a press's poll time is late by at most one frame, so
// two presses delivered by the same or consecutive polls are as close as the user made them.
namespace sb {

class DoubleClickDetector {
 public:
  static constexpr double kMaxGapS = 0.30;     // as ImGui's io.MouseDoubleClickTime
  static constexpr double kMaxMovePx = 6.0;    // as ImGui's io.MouseDoubleClickMaxDist

  // Starts the next event poll: forgets the previous poll's double-click.
  void begin_poll();
  // A press of the button, polled at t_s, at window position (x_px, y_px).
  void press(double t_s, double x_px, double y_px);
  // Whether a press of the current poll completed a double-click.
  bool double_clicked() const { return double_clicked_; }

 private:
  long poll_ = 0;
  bool double_clicked_ = false;
  bool has_first_ = false;        // a press that may start a double-click
  double first_t_s_ = 0, first_x_ = 0, first_y_ = 0;
  long first_poll_ = 0;
};

}  // namespace sb
