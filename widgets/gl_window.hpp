#pragma once
// The GLFW window with its GLX context (VTK's GLEW needs GLX), Dear ImGui on top (OpenGL3 backend,
// "#version 150"), and reading the back buffer for screenshots. One per process.
#include <cstdint>
#include <string>
#include <vector>

#include "core/workbench/input_trickle.hpp"

struct GLFWwindow;

namespace sb::ui {

struct WindowOptions {
  int width = 1280;
  int height = 800;
  bool visible = true;
  bool vsync = false;
  std::string title = "shearbench";
};

// RGB pixels, top row first.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;
};

// The pixels of [x, x + w) x [y, y + h) (top-left origin), clamped to the image.
Image crop(const Image& image, int x, int y, int w, int h);

class GlWindow {
 public:
  explicit GlWindow(const WindowOptions& options);  // throws std::runtime_error without a display
  ~GlWindow();
  GlWindow(const GlWindow&) = delete;
  GlWindow& operator=(const GlWindow&) = delete;

  bool should_close() const;
  void request_close();
  // Polls events (or waits up to `wait_s` when > 0 and no earlier event is still queued) and starts an ImGui
  // frame with the next events that one frame can take without losing one (core/workbench/input_trickle.hpp):
  // a tap polled in one go is seen pressed in one frame and released in the next.
  void begin_frame(double wait_s = 0.0);
  // Renders ImGui into the back buffer. Call read_back_buffer() after this and before present().
  void render();
  void present();
  Image read_back_buffer() const;
  int framebuffer_width() const;
  int framebuffer_height() const;
  GLFWwindow* handle() const { return window_; }

 private:
  using KeyCallback = void (*)(GLFWwindow*, int, int, int, int);
  using MouseButtonCallback = void (*)(GLFWwindow*, int, int, int);
  using CharCallback = void (*)(GLFWwindow*, unsigned int);
  using ScrollCallback = void (*)(GLFWwindow*, double, double);
  // GLFW's callbacks only queue the event; feed() hands it on when its frame comes.
  static void on_key(GLFWwindow* window, int key, int scancode, int action, int mods);
  static void on_mouse_button(GLFWwindow* window, int button, int action, int mods);
  static void on_char(GLFWwindow* window, unsigned int codepoint);
  static void on_cursor_pos(GLFWwindow* window, double x, double y);
  static void on_scroll(GLFWwindow* window, double dx, double dy);
  static void queue(GLFWwindow* window, InputEvent event);
  // To ImGui's backend and the shortcut and double-click recorders (widgets/keys.hpp), once, in order.
  void feed(const InputEvent& event);
  // ImGui's backend reads the live cursor and buttons at NewFrame, which are already those after the whole
  // queue; while events are still queued, a frame sees those after its own events instead.
  void apply_fed_mouse_state() const;
  // A pointer outside the window hovers nothing (a marker's tooltip goes) and fires no shortcut (keys.cpp).
  void forget_pointer_outside() const;

  GLFWwindow* window_ = nullptr;
  KeyCallback imgui_key_callback_ = nullptr;  // ImGui's GLFW backend; feed() calls them
  MouseButtonCallback imgui_mouse_button_callback_ = nullptr;
  CharCallback imgui_char_callback_ = nullptr;
  ScrollCallback imgui_scroll_callback_ = nullptr;
  InputTrickle input_;                  // polled, not yet fed
  static constexpr int kButtons = 8;    // GLFW_MOUSE_BUTTON_LAST + 1, as ImGui's io.MouseDown
  bool button_down_[kButtons] = {};     // after the events fed so far
  bool cursor_fed_ = false;             // whether a cursor move was fed (else the live position stands)
  double cursor_x_ = 0, cursor_y_ = 0;  // the last cursor move fed (window px)
  double last_poll_s_ = 0;  // when the last event poll returned (glfwGetTime); the double-click detector's clock
};

// Writes a PNG atomically (temporary file in the same folder, then rename). Throws std::runtime_error.
void write_png_atomic(const Image& image, const std::string& path);

// True when an X display is reachable (GLFW can open a window).
bool display_available();

}  // namespace sb::ui
