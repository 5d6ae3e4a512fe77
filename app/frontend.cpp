#include "app/frontend.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <iostream>
#include <sstream>

#include <GLFW/glfw3.h>

#include "core/error.hpp"
#include "widgets/panels.hpp"

namespace sb::app {

namespace {
ui::WindowOptions window_options(const FrontendOptions& o) {
  ui::WindowOptions w;
  w.width = o.width;
  w.height = o.height;
  w.visible = o.visible;
  return w;
}
ui::ReplayUi replay_ui(const Session& s) { return s.replay; }
}  // namespace

ui::CameraPreset parse_camera(const std::string& name) {
  if (name == "iso") return ui::CameraPreset::Iso;
  if (name == "top") return ui::CameraPreset::Top;
  if (name == "side") return ui::CameraPreset::Side;
  throw InputError("--camera", "expected iso, top or side, got '" + name + "'");
}

Frontend::Frontend(const SessionOptions& session, const FrontendOptions& options)
    : session_options_(session), options_(options), session_(open_session(session)),
      window_(window_options(options)), workbench_({options.show_timings, options.interactive}) {
  workbench_.set_session(session_.state.get(), session_.measured, session_.title, replay_ui(session_));
  workbench_.set_metrics(field_metrics());
  workbench_.set_camera(parse_camera(options.camera));
  session_.state->set_on_publish([] { glfwPostEmptyEvent(); });
}

Frontend::~Frontend() {
  if (session_.state) session_.state->stop_thread();
}

void Frontend::reopen(const SessionOptions& session) {
  Session next = open_session(session);
  session_.state->stop_thread();
  session_ = std::move(next);
  session_options_ = session;
  workbench_.set_session(session_.state.get(), session_.measured, session_.title, replay_ui(session_));
  session_.state->set_on_publish([] { glfwPostEmptyEvent(); });
  session_.state->start_thread();
}

void Frontend::handle(const ui::WorkbenchRequest& req, bool before_present) {
  if (req.quit) quit_ = true;
  if (req.screenshot) screenshot_pending_ = true;
  if (before_present && screenshot_pending_) {
    screenshot_pending_ = false;
    char name[64];
    const std::time_t t = std::time(nullptr);
    std::strftime(name, sizeof name, "screenshots/shearbench_%Y%m%d_%H%M%S.png", std::localtime(&t));
    ui::write_png_atomic(window_.read_back_buffer(), name);
    workbench_.set_message(std::string("saved ") + name);
  }
  try {
    if (req.load_params) {
      load_params_file(*session_.state, *req.load_params);
      workbench_.set_message("loaded " + *req.load_params);
    }
    if (req.save_params) {
      save_params_file(session_.state->snapshot(), *req.save_params);
      workbench_.set_message("saved " + *req.save_params);
    }
    if (req.open_sample) {
      SessionOptions o = session_options_;
      o.sample_id = session_.replay.samples.at(*req.open_sample);
      o.dataset_dir = session_.replay.dataset_dir;
      o.scene_path.clear();
      reopen(o);
    }
    if (req.open_dataset) {
      SessionOptions o = session_options_;
      o.dataset_dir = *req.open_dataset;
      o.sample_id.clear();
      o.scene_path.clear();
      reopen(o);
      workbench_.set_message("opened " + *req.open_dataset);
    }
  } catch (const std::exception& e) {
    workbench_.set_message(std::string("error: ") + e.what());
  }
}

bool Frontend::frame() {
  // Idle (nothing playing, dragging or computing): sleep until input or a physics publish (which posts
  // an empty event), redraw at least every 0.5 s.
  constexpr double kIdleWaitS = 0.5;
  window_.begin_frame(workbench_.animating() ? 0.0 : kIdleWaitS);
  const auto t_start = std::chrono::steady_clock::now();
  const ui::WorkbenchRequest req = workbench_.draw(frame_ms_);
  window_.render();
  handle(req, true);
  window_.present();
  // Frame time excludes the idle wait: it is what drawing costs.
  frame_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_start).count();
  return !quit_ && !window_.should_close();
}

ui::Image Frontend::render_still(int frames) {
  ui::Image img;
  for (int i = 0; i < frames; ++i) {
    window_.begin_frame();
    workbench_.draw(0.0);
    window_.render();
    if (i + 1 == frames) img = window_.read_back_buffer();
    window_.present();
  }
  return img;
}

std::vector<double> Frontend::profile_drag(int frames) {
  AppState& state = *session_.state;
  const AppSnapshot s0 = state.snapshot();
  // Press to 0.8 mm below the first pose's contact height... the scene's deepest pose is a safe "pressed" pose.
  Pose pressed = s0.X_EI;
  double zmin = 1e9;
  for (const Pose& X : state.path()) zmin = std::min(zmin, X.translation().z());
  if (zmin < 1e9) pressed.translation().z() = zmin;
  state.start_thread();
  std::vector<double> ms;
  double draw_ms_sum = 0, imgui_ms_sum = 0, present_ms_sum = 0;
  constexpr double kRadiusM = 2.0e-3;      // circle radius of the synthetic drag
  constexpr double kTurnsPerFrame = 1.0 / 120.0;
  for (int i = 0; i < frames; ++i) {
    Pose X = pressed;
    const double a = 2 * M_PI * kTurnsPerFrame * i;
    X.translation().x() += kRadiusM * std::cos(a);
    X.translation().y() += kRadiusM * std::sin(a);
    state.request_drag(X);
    using clock = std::chrono::steady_clock;
    const auto ms_since = [](clock::time_point t) { return std::chrono::duration<double, std::milli>(clock::now() - t).count(); };
    const auto t0 = clock::now();
    window_.begin_frame();
    workbench_.draw(frame_ms_);  // includes the VTK render of the 3D view
    const auto t1 = clock::now();
    window_.render();
    const auto t2 = clock::now();
    window_.present();
    frame_ms_ = ms_since(t0);
    ms.push_back(frame_ms_);
    draw_ms_sum += std::chrono::duration<double, std::milli>(t1 - t0).count();
    imgui_ms_sum += std::chrono::duration<double, std::milli>(t2 - t1).count();
    present_ms_sum += ms_since(t2);
  }
  state.stop_thread();
  if (frames > 0)
    std::printf("  mean per frame: widgets + VTK 3D view %.1f ms, ImGui GL draw %.1f ms, swap %.1f ms\n",
                draw_ms_sum / frames, imgui_ms_sum / frames, present_ms_sum / frames);
  return ms;
}

std::string percentiles_line(std::vector<double> ms) {
  if (ms.empty()) return "no frames";
  std::sort(ms.begin(), ms.end());
  const auto pct = [&](double p) { return ms[std::min(ms.size() - 1, static_cast<std::size_t>(p * (ms.size() - 1) + 0.5))]; };
  char buf[200];
  std::snprintf(buf, sizeof buf, "%zu frames: p50 %.1f ms (%.1f fps)  p90 %.1f ms  p99 %.1f ms  max %.1f ms",
                ms.size(), pct(0.5), 1000.0 / pct(0.5), pct(0.9), pct(0.99), ms.back());
  return buf;
}

std::string text_report(const AppSnapshot& snap) {
  std::ostringstream r;
  r << "step " << snap.step << " of " << snap.num_steps - 1 << " (t = " << std::max(0, snap.step) * snap.dt_s << " s)\n";
  for (const auto& m : snap.models) {
    double max_px = 0, sum = 0;
    int contact = 0;
    for (const Vec2& d : m.out.disp_px) {
      max_px = std::max(max_px, d.norm());
      sum += d.norm();
    }
    for (auto c : m.out.marker_in_contact) contact += c != 0;
    char buf[256];
    std::snprintf(buf, sizeof buf, "  %-18s step %7.2f ms (mean of %ld)  |d| max %.3f px  mean %.3f px  markers in contact %d\n",
                  ui::display_name(m.id).c_str(), m.timing.mean_ms, m.timing.count, max_px,
                  m.out.disp_px.empty() ? 0.0 : sum / m.out.disp_px.size(), contact);
    r << buf;
  }
  return r.str();
}

}  // namespace sb::app
