#include "widgets/gl_window.hpp"

#include <algorithm>

#include "core/base/atomic_write.hpp"
#include "widgets/keys.hpp"

#include <GL/glew.h>
// GLEW before GLFW: GLFW must not pull in the system GL header first.
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <cfloat>
#include <cstdlib>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace sb::ui {

namespace {
// DejaVu Sans at this size stays readable in 245 px wide field panels and in screenshots.
constexpr float kFontSizePx = 15.0f;
const char* const kFontPath = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

void glfw_error(int code, const char* what) {
  (void)code;
  (void)what;
}
}  // namespace

bool display_available() {
  const char* d = std::getenv("DISPLAY");
  return d != nullptr && *d != '\0';
}

GlWindow::GlWindow(const WindowOptions& options) {
  glfwSetErrorCallback(glfw_error);
  if (!display_available() || !glfwInit())
    throw std::runtime_error("cannot open a window: no X display (DISPLAY is not set or unreachable)");
  // VTK's GLEW is the GLX build: keep GLFW's default GLX context, 3.2 core forward-compatible.
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 2);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GL_TRUE);
  glfwWindowHint(GLFW_VISIBLE, options.visible ? GLFW_TRUE : GLFW_FALSE);
  glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
  glfwWindowHint(GLFW_SAMPLES, 0);
  window_ = glfwCreateWindow(options.width, options.height, options.title.c_str(), nullptr, nullptr);
  if (window_ == nullptr) {
    glfwTerminate();
    throw std::runtime_error("cannot create an OpenGL 3.2 core window on this display");
  }
  glfwMakeContextCurrent(window_);
  glfwSwapInterval(options.vsync ? 1 : 0);
  glewExperimental = GL_TRUE;
  glewInit();
  glGetError();  // GLEW's probe of a core context leaves GL_INVALID_ENUM behind

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;  // a fixed layout, the same in every run and in the render tests
  if (std::filesystem::exists(kFontPath)) io.Fonts->AddFontFromFileTTF(kFontPath, kFontSizePx);
  ImGui::StyleColorsDark();
  ImGuiStyle& style = ImGui::GetStyle();
  style.WindowRounding = 0;
  style.FrameRounding = 2;
  style.WindowBorderSize = 1;
  ImGui_ImplGlfw_InitForOpenGL(window_, true);
  // After ImGui's callbacks are installed: ours queue the events and feed() forwards them to ImGui's, a frame's
  // worth at a time, and records presses for the shortcuts. ImGui 1.86 has no cursor callback (it reads the
  // cursor at NewFrame): ours tracks the position each frame's events leave.
  imgui_key_callback_ = glfwSetKeyCallback(window_, &GlWindow::on_key);
  imgui_mouse_button_callback_ = glfwSetMouseButtonCallback(window_, &GlWindow::on_mouse_button);
  imgui_char_callback_ = glfwSetCharCallback(window_, &GlWindow::on_char);
  imgui_scroll_callback_ = glfwSetScrollCallback(window_, &GlWindow::on_scroll);
  glfwSetCursorPosCallback(window_, &GlWindow::on_cursor_pos);
  glfwSetWindowUserPointer(window_, this);
  ImGui_ImplOpenGL3_Init("#version 150");
}

GlWindow::~GlWindow() {
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(window_);
  glfwTerminate();
}

bool GlWindow::should_close() const { return glfwWindowShouldClose(window_); }
void GlWindow::request_close() { glfwSetWindowShouldClose(window_, GLFW_TRUE); }

static_assert(InputEvent::kRelease == GLFW_RELEASE && InputEvent::kPress == GLFW_PRESS &&
              InputEvent::kRepeat == GLFW_REPEAT);
static_assert(GLFW_MOUSE_BUTTON_LAST + 1 == 8);

void GlWindow::queue(GLFWwindow* window, InputEvent event) {
  auto* self = static_cast<GlWindow*>(glfwGetWindowUserPointer(window));
  if (self == nullptr) return;
  event.t_s = glfwGetTime();
  self->input_.push(event);
}

void GlWindow::on_key(GLFWwindow* window, int key, int scancode, int action, int mods) {
  queue(window, InputEvent::key(key, scancode, action, mods));
}
void GlWindow::on_mouse_button(GLFWwindow* window, int button, int action, int mods) {
  queue(window, InputEvent::mouse_button(button, action, mods));
}
void GlWindow::on_char(GLFWwindow* window, unsigned int codepoint) { queue(window, InputEvent::character(codepoint)); }
void GlWindow::on_cursor_pos(GLFWwindow* window, double x, double y) { queue(window, InputEvent::cursor(x, y)); }
void GlWindow::on_scroll(GLFWwindow* window, double dx, double dy) { queue(window, InputEvent::scroll(dx, dy)); }

void GlWindow::feed(const InputEvent& e) {
  switch (e.kind) {
    case InputEvent::Kind::kKey:
      if (imgui_key_callback_ != nullptr) imgui_key_callback_(window_, e.code, e.scancode, e.action, e.mods);
      record_key_event(e.code, e.action, e.mods);
      break;
    case InputEvent::Kind::kMouseButton:
      if (imgui_mouse_button_callback_ != nullptr) imgui_mouse_button_callback_(window_, e.code, e.action, e.mods);
      if (e.code >= 0 && e.code < kButtons) button_down_[e.code] = e.action != GLFW_RELEASE;
      if (e.code == GLFW_MOUSE_BUTTON_LEFT && e.action == GLFW_PRESS) {
        double x = cursor_x_, y = cursor_y_;
        if (!cursor_fed_) glfwGetCursorPos(window_, &x, &y);
        record_left_press(e.t_s, x, y);
      }
      break;
    case InputEvent::Kind::kChar:
      if (imgui_char_callback_ != nullptr) imgui_char_callback_(window_, static_cast<unsigned>(e.code));
      break;
    case InputEvent::Kind::kCursorPos:
      cursor_fed_ = true;
      cursor_x_ = e.x;
      cursor_y_ = e.y;
      break;
    case InputEvent::Kind::kScroll:
      if (imgui_scroll_callback_ != nullptr) imgui_scroll_callback_(window_, e.x, e.y);
      break;
  }
}

void GlWindow::apply_fed_mouse_state() const {
  // With nothing left queued the live state is the fed one (and, for a cursor outside the window, the newer).
  if (input_.empty()) return;
  ImGuiIO& io = ImGui::GetIO();
  for (int b = 0; b < kButtons && b < IM_ARRAYSIZE(io.MouseDown); ++b) io.MouseDown[b] = button_down_[b];
  // -FLT_MAX: the backend found the cursor outside an unfocused window; that stands.
  if (cursor_fed_ && io.MousePos.x > -FLT_MAX / 2)
    io.MousePos = ImVec2(static_cast<float>(cursor_x_), static_cast<float>(cursor_y_));
}

// The backend reports a focused window's cursor wherever it is, and our fed position is the last one inside (GLFW
// reports moves inside only): an ImGui that saw either kept hovering what the pointer left. While a button is held
// (a drag that leaves the window) ImGui keeps following the pointer.
void GlWindow::forget_pointer_outside() const {
  ImGuiIO& io = ImGui::GetIO();
  for (int b = 0; b < kButtons && b < IM_ARRAYSIZE(io.MouseDown); ++b)
    if (io.MouseDown[b]) return;
  double x = 0, y = 0;
  glfwGetCursorPos(window_, &x, &y);
  int w = 0, h = 0;
  glfwGetWindowSize(window_, &w, &h);
  if (x < 0 || y < 0 || x >= w || y >= h) io.MousePos = ImVec2(-FLT_MAX, -FLT_MAX);
}

void GlWindow::begin_frame(double wait_s) {
  clear_key_presses();  // presses of a frame that did not ask for them are not replayed later
  begin_mouse_poll(last_poll_s_ > 0 ? glfwGetTime() - last_poll_s_ : 0.0);
  // Events still queued are the next frames' input: no waiting while they are.
  if (wait_s > 0 && input_.empty())
    glfwWaitEventsTimeout(wait_s);
  else
    glfwPollEvents();
  last_poll_s_ = glfwGetTime();
  for (const InputEvent& e : input_.take_frame()) feed(e);
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  apply_fed_mouse_state();
  forget_pointer_outside();
  ImGui::NewFrame();
}

void GlWindow::render() {
  ImGui::Render();
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(0, 0, framebuffer_width(), framebuffer_height());
  glDisable(GL_SCISSOR_TEST);
  glClearColor(0.10f, 0.10f, 0.11f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

void GlWindow::present() { glfwSwapBuffers(window_); }

int GlWindow::framebuffer_width() const {
  int w = 0, h = 0;
  glfwGetFramebufferSize(window_, &w, &h);
  return w;
}
int GlWindow::framebuffer_height() const {
  int w = 0, h = 0;
  glfwGetFramebufferSize(window_, &w, &h);
  return h;
}

Image GlWindow::read_back_buffer() const {
  Image img;
  img.width = framebuffer_width();
  img.height = framebuffer_height();
  img.rgb.resize(static_cast<std::size_t>(img.width) * img.height * 3);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glReadBuffer(GL_BACK);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, img.width, img.height, GL_RGB, GL_UNSIGNED_BYTE, img.rgb.data());
  // OpenGL rows start at the bottom.
  const std::size_t row = static_cast<std::size_t>(img.width) * 3;
  for (int y = 0; y < img.height / 2; ++y)
    std::swap_ranges(img.rgb.begin() + y * row, img.rgb.begin() + (y + 1) * row,
                     img.rgb.begin() + (img.height - 1 - y) * row);
  return img;
}

Image crop(const Image& image, int x, int y, int w, int h) {
  const int x0 = std::clamp(x, 0, image.width), y0 = std::clamp(y, 0, image.height);
  const int x1 = std::clamp(x + w, x0, image.width), y1 = std::clamp(y + h, y0, image.height);
  Image out;
  out.width = x1 - x0;
  out.height = y1 - y0;
  out.rgb.resize(static_cast<std::size_t>(out.width) * out.height * 3);
  for (int r = 0; r < out.height; ++r)
    std::copy_n(image.rgb.begin() + (static_cast<std::size_t>(y0 + r) * image.width + x0) * 3,
                static_cast<std::size_t>(out.width) * 3, out.rgb.begin() + static_cast<std::size_t>(r) * out.width * 3);
  return out;
}

void write_png_atomic(const Image& image, const std::string& path) {
  cv::Mat rgb(image.height, image.width, CV_8UC3, const_cast<std::uint8_t*>(image.rgb.data()));
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  sb::write_png_atomic(path, bgr.rows, bgr.cols, bgr.channels(), bgr.data);
}

}  // namespace sb::ui
