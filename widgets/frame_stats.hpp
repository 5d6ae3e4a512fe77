#pragma once
// `gui --stats FILE`: what a long session costs, measured from inside the workbench. Every `interval_s`
// one JSON line is appended: the frame-time percentiles over that window (drawing only, the idle wait
// excluded, as the status bar shows), resident memory from /proc/self/statm, open file descriptors, and
// the live GL objects of the window's context (textures, buffers, framebuffers, renderbuffers, vertex
// arrays, programs, shaders), counted by asking GL about every name up to the highest one handed out.
// The soak (tests/cli/soak.py) reads these lines to see memory or GL objects grow over an hour.
#include <chrono>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace sb::ui {

// Live GL objects of the current context by kind ("textures", "buffers", ...). Needs a current context.
std::map<std::string, int> gl_object_counts();
// Resident set size (kB) from /proc/self/statm; -1 when it cannot be read.
long resident_kb();
// Open file descriptors of this process (entries of /proc/self/fd); -1 when it cannot be read.
int open_fds();

class FrameStats {
 public:
  FrameStats() = default;
  // Appends to `path` (created when missing); throws std::runtime_error naming the file when it cannot.
  FrameStats(const std::string& path, double interval_s);
  bool enabled() const { return out_.is_open(); }
  // One drawn frame; writes a line when the window is over (call with the GL context current).
  void add(double frame_ms);

 private:
  void write_line(double now_s);
  std::ofstream out_;
  std::string path_;
  double interval_s_ = 10;
  double start_s_ = 0, window_start_s_ = 0;
  std::vector<double> ms_;
};

}  // namespace sb::ui
