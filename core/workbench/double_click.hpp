#pragma once
// Double-clicks from the window's mouse events rather than from ImGui's frame clock. ImGui 1.86 sees a
// press only as "down at NewFrame" and times a double-click between frames with a 0.30 s window, so on a
// slow frame (llvmpipe under load draws one in 150-500 ms) two quick presses were not a double-click, and
// two presses polled in one frame counted as one. Here every press is recorded when it is polled. A press
// that arrives while the program waits for events is polled at once; one that arrives during a frame's
// work waits at most that frame's busy time. So two presses polled t apart, the second after a frame
// busy for b, were made at least t - b apart: a double-click when t - b is within kMaxGapS.
namespace sb {

class DoubleClickDetector {
 public:
  // The desktops' own double-click time (Windows 500 ms, GTK 400 ms; ImGui's 300 ms is tighter). Under
  // load the X server itself delivers events late and in bursts (measured: two presses made 0.2 s apart
  // reached the workbench 0.57 s apart with llvmpipe and six busy processes on two cores).
  static constexpr double kMaxGapS = 0.50;
  static constexpr double kMaxMovePx = 6.0;  // as ImGui's io.MouseDoubleClickMaxDist

  // Starts the next event poll, after a frame whose work (not counting the wait for events) took busy_s:
  // forgets the previous poll's double-click.
  void begin_poll(double busy_s);
  // A press of the button, polled at t_s, at window position (x_px, y_px).
  void press(double t_s, double x_px, double y_px);
  // Whether a press of the current poll completed a double-click.
  bool double_clicked() const { return double_clicked_; }

 private:
  double busy_s_ = 0;  // the work of the frame before the current poll
  bool double_clicked_ = false;
  bool has_first_ = false;  // a press that may start a double-click
  double first_t_s_ = 0, first_x_ = 0, first_y_ = 0;
};

}  // namespace sb
