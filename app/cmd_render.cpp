// `shearbench render`: draws exactly what the GUI draws (same Workbench::draw on a GLFW window, visible
// or not), at one step of a scene or dataset sample, and writes a PNG. Needs an X display: without one
// run it under `xvfb-run -a -s "-screen 0 1600x900x24"`.
#include <cmath>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>

#include "core/base/error.hpp"
#include "core/base/reproducible.hpp"

#include "app/command.hpp"
#include "app/frontend.hpp"

namespace sb::app {
namespace {

struct RenderArgs {
  std::string session;
  SessionSource open;
  std::string size = "1600x900", out, camera = "iso";
  int step = -2;   // -2: the last step
  int frame = -2;  // dataset frame (same as step)
  int profile = 0;
  bool no_timings = false;
  bool report = false;
  bool visible = false;
  std::string panel;
  std::string export_fields;  // folder: every model's field along the path (tsd/1), as the GUI's Export         // crop
                              // the PNG to one panel (3D view, a model's name, Measured)
  std::string residual;       // residual JSON: Residual section open, corrected model in its panel
  bool residual_fields = false;
  std::string drag_mm;        // "x,y,z": after reaching the step, drag the indenter there (mm, in E)
  double drag_twist_deg = 0;  // ... twisting it about the pad normal by this much
  std::string enlarge;        // a field panel's name: drawn enlarged to the whole field area
  int hover_marker = -1;      // a marker's tooltip shown as if hovered
};

Vec3 parse_mm_triple(const std::string& text) {
  Vec3 v;
  char c1 = 0, c2 = 0;
  std::istringstream in(text);
  if (!(in >> v.x() >> c1 >> v.y() >> c2 >> v.z()) || c1 != ',' || c2 != ',' || !v.allFinite())
    throw InputError("--drag-mm", "expected x,y,z in millimetres, got '" + text + "'");
  return v * 1e-3;
}

int run_render(const RenderArgs& args, const GlobalOptions& g) {
  RenderArgs a = args;
  if (a.session.empty()) open_report_dataset(a.open, a.residual, g.data_root_flag);  // as gui does
  const SessionOptions so{a.open, g.data_root_flag};
  FrontendOptions fo;
  std::tie(fo.width, fo.height) = parse_size(a.size);
  fo.visible = a.visible;
  fo.show_timings = !a.no_timings && timings_in_outputs();  // --reproducible: no timing text
  fo.interactive = false;
  fo.camera = a.camera;
  Frontend front(so, fo);
  std::optional<int> session_step;
  if (!a.session.empty()) {
    // A saved (or autosaved) session: the same restore path as the GUI, then run headless here.
    front.open_session_file(a.session);
    front.session().state->stop_thread();
    session_step = load_session_file(a.session).step;
  }
  if (!a.residual.empty()) {
    if (!front.load_residual(a.residual)) throw InputError("--residual", front.workbench().message());
    front.workbench().set_residual_view(a.residual_fields, true);
    front.workbench().apply_residual_base_params();  // the base beside the corrected model, both fitted
  }
  if (!a.enlarge.empty() && !front.workbench().set_enlarged(a.enlarge))
    throw InputError("--enlarge", "no field panel '" + a.enlarge + "' (the models' names as shown, Measured)");
  front.workbench().set_hover_marker(a.hover_marker);
  AppState& state = *front.session().state;
  if (a.profile > 0) {
    const auto ms = front.profile_drag(a.profile);
    std::cout << "profile (" << fo.width << "x" << fo.height << ", 3D view + " << state.num_models() + 1
              << " panels, synthetic drag): " << percentiles_line(ms) << "\n";
    std::cout << "physics: " << state.current_step() + 1 << " model steps during the drag\n";
  } else {
    const int last = session_step ? *session_step : static_cast<int>(state.path().size()) - 1;
    const int target = a.frame != -2 ? a.frame : a.step != -2 ? a.step : last;
    state.run_to(target);
    if (!a.drag_mm.empty() || a.drag_twist_deg != 0) {
      // The GUI's drag path: queued at the sync point, sub-stepped, run by tick() to its end.
      Pose X = state.snapshot().X_EI;
      if (!a.drag_mm.empty()) X.translation() = parse_mm_triple(a.drag_mm);
      X.linear() = Rz(a.drag_twist_deg * M_PI / 180.0) * X.linear();
      state.request_drag(X);
      while (state.tick()) {
      }
    }
  }
  // ImGui lays a fixed-size window out on its first frame and draws it settled on the second.
  constexpr int kSettleFrames = 3;
  ui::Image img = front.render_still(kSettleFrames);
  if (!a.panel.empty()) img = front.crop_to_region(img, a.panel);
  if (!a.export_fields.empty()) front.export_fields(a.export_fields);
  ui::write_png_atomic(img, a.out);
  if (!g.quiet)
    std::cout << "wrote " << std::filesystem::absolute(a.out).string() << " (" << img.width << "x" << img.height
              << ")\n";
  if (a.report) std::cout << text_report(state.snapshot());
  return 0;
}

void add_flags(CLI::App& sub, RenderArgs& a) {
  add_source_options(sub, a.open);
  sub.add_option("--session", a.session, "a saved or autosaved session file (JSON)");
  sub.add_option("--frame", a.frame, "dataset frame to show (= step)");
  sub.add_option("--step", a.step, "step to show (default: the last)");
  sub.add_option("--size", a.size, "window size WIDTHxHEIGHT")->capture_default_str();
  sub.add_option("--camera", a.camera, "iso | top | side")->capture_default_str();
  sub.add_option("--out", a.out, "PNG to write")->required();
  sub.add_option("--profile", a.profile, "first run N frames of a synthetic drag and print frame-time percentiles");
  sub.add_flag("--no-timings", a.no_timings, "hide timings in the status bar (deterministic images)");
  sub.add_flag("--report", a.report, "print model step times and field magnitudes");
  sub.add_option("--drag-mm", a.drag_mm, "then drag the indenter to x,y,z (mm)");
  sub.add_option("--drag-twist-deg", a.drag_twist_deg, "... twisting it by this angle about the normal");
  sub.add_flag("--visible", a.visible, "show the window while rendering");
  sub.add_option("--panel", a.panel,
                 "write only this panel: '3D view', a model's name as shown (e.g. 'FOTS'), 'Measured'");
  sub.add_option("--enlarge", a.enlarge,
                 "draw this field panel enlarged to the whole field area (e.g. 'FOTS', 'Measured')");
  sub.add_option("--hover-marker", a.hover_marker, "show marker N's tooltip (every model's (du, dv)) as if hovered");
  sub.add_option("--export-fields", a.export_fields,
                 "also write every model's field along the path as DIR/<model>/ (tsd/1)");
  sub.add_option("--residual", a.residual,
                 "a residual analysis (shearbench residual --json): ranked effects, its model at the fitted base "
                 "parameters, and the corrected model");
  sub.add_flag("--residual-fields", a.residual_fields, "draw measured - model instead of the model fields");
}

const Subcommand<RenderArgs> kRenderCommand{
    "render", "draw the workbench headless (what `gui` shows) at one step into a PNG", 60, add_flags, run_render};

}  // namespace
}  // namespace sb::app
