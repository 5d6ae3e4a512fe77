#include "app/frontend.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <thread>

#include <GLFW/glfw3.h>

#include <cctype>

#include <imgui.h>

#include "core/base/data_root.hpp"
#include "core/base/display_path.hpp"
#include "core/base/error.hpp"
#include "core/base/free_memory.hpp"
#include "core/data/json_read.hpp"
#include "core/effects/model_spec.hpp"
#include "core/models/model_family.hpp"
#include "core/workbench/field_export.hpp"
#include "core/workbench/output_folder.hpp"
#include "core/workbench/report_dataset.hpp"
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
  if (name == "iso") return ui::CameraPreset::kIso;
  if (name == "top") return ui::CameraPreset::kTop;
  if (name == "side") return ui::CameraPreset::kSide;
  throw InputError("--camera", "expected iso, top or side, got '" + name + "'");
}

Frontend::Frontend(const SessionOptions& session, const FrontendOptions& options)
    : session_options_(session),
      options_(options),
      session_(open_session(session)),
      window_(window_options(options)),
      workbench_({options.show_timings, options.interactive}),
      keeper_(options.autosave_interval_s,
              options.autosave_path.empty() ? default_autosave_path() : options.autosave_path,
              {[this] { return session_.state->pending_edits(); }, [this] { return current_session_file(); }}),
      loader_([] { glfwPostEmptyEvent(); }) {
  workbench_.set_session(session_.state.get(), session_.measured, session_.title, replay_ui(session_));
  workbench_.set_param_set(session_.param_set, session_.scene.sensor_model, session_.loop_answer_model);
  workbench_.set_metrics(field_metrics());
  workbench_.set_data_root(resolve_data_root(session.data_root));
  workbench_.set_camera(parse_camera(options.camera));
  session_.state->set_on_publish([] { glfwPostEmptyEvent(); });
  workbench_.set_session_path(default_session_path());  // never the working folder (often the repository)
  refresh_open_choices();
}

Frontend::~Frontend() {
  if (session_.state) session_.state->stop_thread();
}

void Frontend::reopen(const SessionOptions& session, Baseline baseline) {
  install_session(open_session(session), session, baseline);
}

// The one place a new session replaces the running one (the sync point of a reopen).
void Frontend::install_session(Session next, const SessionOptions& options, Baseline baseline) {
  // A residual analysis belongs to its dataset: another dataset (or a scene) drops it, and with it
  // "Apply the fitted base parameters".
  if (next.scene.dataset_dir != session_.scene.dataset_dir) workbench_.clear_residual();
  session_.state->stop_thread();
  session_ = std::move(next);
  session_options_ = options;
  workbench_.set_session(session_.state.get(), session_.measured, session_.title, replay_ui(session_));
  workbench_.set_param_set(session_.param_set, session_.scene.sensor_model, session_.loop_answer_model);
  session_.state->set_on_publish([] { glfwPostEmptyEvent(); });
  session_.state->start_thread();
  keeper_.expect_baseline(baseline);
  refresh_open_choices();
}

void Frontend::reopen_then(const SessionOptions& session, Baseline baseline, const std::string& what,
                           std::function<void()> then) {
  if (!options_.interactive) {
    reopen(session, baseline);
    if (then) then();
    return;
  }
  loader_.start(session, baseline, what, std::move(then), now_s());
  workbench_.set_loading(what);
}

// At the start of a frame: a finished open is swapped in here, never mid-frame.
void Frontend::poll_load() {
  std::optional<SessionLoader::Opened> opened = loader_.take_finished(now_s());
  if (!opened) return;
  workbench_.set_loading("");
  if (!opened->session) {
    workbench_.set_message("error: " + opened->error);
    workbench_.revert_session_path();
    return;
  }
  try {
    const double t0 = now_s();
    install_session(std::move(*opened->session), opened->options, opened->baseline);
    char buf[96];
    std::snprintf(buf, sizeof buf, "; read in %.1f s on a worker, swapped in %.0f ms)", opened->read_s,
                  1e3 * (now_s() - t0));
    workbench_.set_message("opened " + opened->what + " (parameter set " + session_.param_set.name + buf +
                           (session_.beside_note.empty() ? "" : "; " + session_.beside_note) +
                           (announce_replaced_work_ ? "; your unsaved work is kept: Ctrl+Z brings it back" : ""));
    announce_replaced_work_ = false;
    if (opened->then) opened->then();
  } catch (const std::exception& e) {
    workbench_.set_message(std::string("error: ") + e.what());
  }
}

// What the Open list offers: this run's recent opens, the scenes in scenes/ and the data root's datasets.
void Frontend::refresh_open_choices() {
  std::vector<std::string> choices = recent_.paths();
  const std::string scenes = std::filesystem::is_directory("scenes") ? "scenes" : "";
  for (const std::string& p : open_suggestions(resolve_data_root(session_options_.data_root), scenes))
    if (std::find(choices.begin(), choices.end(), p) == choices.end()) choices.push_back(p);
  workbench_.replay_ui().choices = std::move(choices);
}

void Frontend::open_path(const std::string& typed, bool from_session_field) {
  const std::string root = resolve_data_root(session_options_.data_root);
  OpenTarget t;
  try {
    t = classify_open_target(typed, root, std::filesystem::current_path().string());
  } catch (...) {
    if (from_session_field) workbench_.revert_session_path();  // a failed open adopts nothing
    throw;
  }
  recent_.add(typed);
  if (t.kind == OpenKind::kSession) {
    open_session_file(t.path);
    return;
  }
  SessionOptions o = session_options_;
  o.open.sample_id.clear();
  o.open.param_set.clear();  // the set for the new sensor (a Mini set is meaningless on a TacTip)
  o.open.indenter_mesh.clear();
  if (t.kind == OpenKind::kDataset) {
    o.open.dataset_dir = data_path(t.path, root);  // "data:twin/..." stays portable in the session file
    o.open.scene_path.clear();
  } else {
    o.open.scene_path = t.path;
    o.open.dataset_dir.clear();
  }
  if (from_session_field) workbench_.revert_session_path();  // a scene or dataset is not the session file
  const std::string what = display_path(t.path, root);
  reopen_then(o, Baseline::kNone, what);
}

void Frontend::handle(const ui::WorkbenchRequest& req, bool before_present) {
  if (req.quit) quit_ = true;
  if (req.screenshot) {
    screenshot_pending_ = true;
    screenshot_region_ = req.screenshot_region;
  }
  if (before_present && screenshot_pending_) {
    screenshot_pending_ = false;
    char stamp[32];
    const std::time_t t = std::time(nullptr);
    std::strftime(stamp, sizeof stamp, "%Y%m%d_%H%M%S", std::localtime(&t));
    std::string name = output_path(std::string("shearbench_") + stamp, output_folder());
    ui::Image img = window_.read_back_buffer();
    if (!screenshot_region_.empty()) {
      img = crop_to_region(img, screenshot_region_);
      name += "_" + file_slug(screenshot_region_);
    }
    ui::write_png_atomic(img, name + ".png");
    // The name only: a whole path wrapped the status bar (the folder is in the Session field's tooltip).
    workbench_.set_message("saved " + std::filesystem::path(name).filename().string() + ".png");
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
    if (req.save_session) save_session_to(*req.save_session);
    if (req.load_residual) load_residual(*req.load_residual);
    if (req.switch_model) switch_model(req.switch_model->first, req.switch_model->second);
    if (req.beside_hydroshear) set_beside_hydroshear(*req.beside_hydroshear);
    if (req.export_fields) start_export(output_path(*req.export_fields, output_folder()));
    if (req.answer) handle_answer(req.answer->first, req.answer->second);
    handle_open_requests(req);
  } catch (const std::exception& e) {
    workbench_.set_message(std::string("error: ") + e.what());
  }
}

// Everything that replaces the session: on the worker (reopen_then), so the window stays live.
void Frontend::handle_open_requests(const ui::WorkbenchRequest& req) {
  if (req.undo_open) bring_back_replaced_work();
  const bool opens = req.open_sample || req.open_session || req.open_dataset || req.param_set;
  if (opens) keep_replaced_work();
  if (req.open_sample) {
    SessionOptions o = session_options_;
    o.open.sample_id = session_.replay.samples.at(*req.open_sample);
    o.open.dataset_dir = session_.replay.dataset_dir;
    o.open.scene_path.clear();
    reopen_then(o, Baseline::kNone, o.open.dataset_dir + " / " + o.open.sample_id);
  }
  if (req.open_session) open_path(*req.open_session, true);
  if (req.open_dataset) open_path(*req.open_dataset, false);
  if (req.param_set) {
    SessionOptions o = session_options_;
    o.open.param_set = *req.param_set;
    const std::string name = *req.param_set;
    reopen_then(o, Baseline::kNone, "parameter set " + name,
                [this, name] { workbench_.set_message("every model starts again from parameter set " + name); });
  }
}

// An open replaces the path, the parameters and their undo history. Over unsaved work it does not ask (a question
// in the way of every open); it keeps the work it replaces, and Ctrl+Z past the new session's first edit brings it
// back. Over saved work there is nothing to keep: the file holds it (and an earlier kept work stays undoable).
void Frontend::keep_replaced_work() {
  if (!options_.keep_work) return;
  SessionFile work = session_file_for_saving();  // waits for the physics to take a nudge made a moment ago
  if (!keeper_.dirty_now(now_s())) return;
  replaced_work_ = ReplacedWork{std::move(work), workbench_.session_path(), session_.title};
  announce_replaced_work_ = true;
  workbench_.set_open_undo("the open: brings back your unsaved work in " + session_.title);
}

// Kept until it is back: an open that fails (its scene deleted meanwhile) leaves it to try again.
void Frontend::bring_back_replaced_work() {
  if (!replaced_work_) return;
  const ReplacedWork work = *replaced_work_;
  // Baseline kNone: the work comes back unsaved, as it was.
  apply_session_file(work.file, Baseline::kNone, [this, work] {
    replaced_work_.reset();
    workbench_.set_open_undo("");
    workbench_.set_session_path(work.session_path);
    workbench_.set_message("brought back your unsaved work in " + work.title + " (not yet saved: Ctrl+S saves it)");
  });
}

// Save / Ctrl+S: the session file is adopted only once written (a refused path is not offered again).
void Frontend::save_session_to(const std::string& path) {
  save_session_file(path, session_file_for_saving());
  keeper_.saved_to(path);
  workbench_.set_saved_once(true);
  workbench_.set_session_path(path);
  workbench_.set_message(
      "saved session " + path +
      (session_.state->pending_edits() > 0 ? " (before the physics took the last edit: it will be autosaved)" : ""));
}

bool Frontend::frame() {
  // Idle (nothing playing, dragging or computing): sleep until input or a physics publish (which posts
  // an empty event), redraw at least every 0.5 s.
  constexpr double kIdleWaitS = 0.5;
  window_.begin_frame(workbench_.animating() ? 0.0 : kIdleWaitS);
  const auto t_start = std::chrono::steady_clock::now();
  poll_load();
  if (workbench_.session_path() != output_folder_for_) {  // the folder follows the session file
    output_folder_for_ = workbench_.session_path();
    workbench_.set_output_folder(output_folder());
  }
  const ui::WorkbenchRequest req = workbench_.draw(frame_ms_);
  window_.render();
  handle(req, true);
  window_.present();
  // Frame time excludes the idle wait: it is what drawing costs.
  frame_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_start).count();
  stats_.add(frame_ms_);
  if (options_.keep_work) keep_work_tick();
  update_window_title();
  trim_memory_when_idle();
  if (!quit_ && !window_.should_close()) return true;
  return allow_close();
}

ui::Image Frontend::crop_to_region(const ui::Image& image, const std::string& region) const {
  for (const auto& r : workbench_.regions())
    if (r.name == region) {
      // Regions are in window pixels; the image is in framebuffer pixels (HiDPI scales them).
      const ImVec2 s = ImGui::GetIO().DisplayFramebufferScale;
      return ui::crop(image, static_cast<int>(std::lround(r.x * s.x)), static_cast<int>(std::lround(r.y * s.y)),
                      static_cast<int>(std::lround(r.w * s.x)), static_cast<int>(std::lround(r.h * s.y)));
    }
  throw InputError("--panel", "no panel '" + region + "' (3D view, the models' names, Measured)");
}

std::string file_slug(const std::string& text) {
  std::string slug;
  for (char c : text) {
    if (std::isalnum(static_cast<unsigned char>(c)))
      slug += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    else if (!slug.empty() && slug.back() != '_')
      slug += '_';
  }
  while (!slug.empty() && slug.back() == '_') slug.pop_back();
  return slug;
}

// Every model at its current parameters, run afresh on the export worker (not the physics thread's
// instances) along a copy of the current path.
FieldExportRequest Frontend::export_request(const std::string& dir) const {
  const AppState& state = *session_.state;
  const AppSnapshot snap = state.snapshot();
  FieldExportRequest r;
  r.dir = dir;
  r.title = session_.title;
  if (!session_options_.open.sample_id.empty()) r.sample_id = session_options_.open.sample_id;
  r.sensor = state.sensor();
  r.indenter = state.indenter();
  for (const auto& m : snap.models) r.models.push_back({m.id, m.params});
  r.path = state.path();
  r.dt_s = snap.dt_s;
  return r;
}

void Frontend::start_export(const std::string& dir) {
  FieldExportRequest r = export_request(dir);
  check_export_target(r);  // a refused folder is reported now, not by the worker
  workbench_.start_export(std::move(r));
  workbench_.set_message("exporting fields to " + dir + " ...");
}

int Frontend::export_fields(const std::string& dir) {
  start_export(dir);
  workbench_.wait_for_export();
  const FieldExportStatus st = workbench_.export_status();
  if (st.phase != FieldExportStatus::Phase::kDone)
    throw std::runtime_error("field export to " + dir + ": " + (st.error.empty() ? "did not finish" : st.error));
  return st.written;
}

void Frontend::switch_model(int slot, const std::string& model_id) {
  AppState& state = *session_.state;
  auto model = make_spec_model(model_id, state.sensor(), state.indenter());
  model->set_params(session_.param_set.params(model_id));  // the variant starts from the set too
  state.request_model(static_cast<std::size_t>(slot), std::move(model));
  // The session remembers the variant (what `gui --hydroshear/--fots/--tacsl` would open).
  if (const ModelFamily* f = find_model_family_of_form(model_id.substr(0, model_id.find('+'))))
    session_options_.open.form_shown(f->id) = model_id;
  workbench_.set_message("switched to " + ui::display_name(model_id));
}

// One more model slot is a new session holding everything the user had (path, step, parameters, display):
// the physics' slots are fixed while it runs. The change itself is an edit: the work is not clean after it.
void Frontend::set_beside_hydroshear(const std::string& model_id) {
  SessionFile f = session_file_for_saving();
  f.open.beside_hydroshear = model_id;
  const std::string done = model_id.empty() ? std::string("removed the panel beside HydroShear")
                                            : ui::display_name(model_id) + " beside HydroShear";
  apply_session_file(f, Baseline::kNone, [this, done] { workbench_.set_message(done); });
}

std::string Frontend::output_folder() const {
  return sb::output_folder(options_.output_folder, workbench_.session_path(), default_user_output_folder(),
                           inside_git_checkout);
}

// A report over another dataset (or a scene) would put its corrected model beside HydroShear on data it
// was never computed on: refused with a status line naming both (core/workbench/report_dataset).
bool Frontend::load_residual(const std::string& path) {
  ResidualSummary summary = load_residual_summary(path);
  const ReportDatasetCheck check = check_report_dataset(std::filesystem::path(path).filename().string(),
                                                        summary.dataset, session_.scene.dataset_dir);
  if (check.load) workbench_.set_residual(std::move(summary));
  workbench_.set_message(check.message);
  return check.load;
}

// ------------------------------------------------------------------------------------ no lost work

double Frontend::now_s() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

SessionFile Frontend::current_session_file() const {
  const AppSnapshot snap = session_.state->snapshot();
  SessionFile f;
  // Absolute, so the session opens from any working directory ("data:..." stays relative to the data root).
  const auto absolute = [](const std::string& p) {
    return p.empty() || p.rfind("data:", 0) == 0 ? p : std::filesystem::absolute(p).lexically_normal().string();
  };
  f.open = session_options_.open;
  f.open.scene_path = absolute(f.open.scene_path);
  f.open.dataset_dir = absolute(f.open.dataset_dir);
  for (const auto& m : snap.models) f.params[m.id] = m.params.to_json();
  f.path = session_.state->path();
  f.step = snap.step;
  auto& wb = const_cast<ui::Workbench&>(workbench_);
  f.auto_scale = wb.auto_scale_enabled();
  f.arrow_gain = wb.scale().arrow_gain;
  f.colour_max_px = wb.scale().colour_max_px;
  f.camera = wb.camera_view();
  wb.write_display_choices(f);
  f.residual_file = absolute(wb.residual_file());
  f.residual_fields = wb.residual_fields_shown();
  f.residual_corrected = wb.corrected_shown();
  return f;
}

// A save holds every edit made before it: the physics takes queued edits at its next sync point, so a
// Ctrl+S in the frame of a nudge (or while the physics was busy stepping) wrote the path without that nudge,
// and every later save stayed one nudge behind (found by the soak, tests/cli/soak.py). Waits for
// the queue to drain, bounded: a save must not hang the window when the physics thread is not running.
SessionFile Frontend::session_file_for_saving() {
  constexpr auto kMaxWait = std::chrono::seconds(5);
  const auto t0 = std::chrono::steady_clock::now();
  while (session_.state->pending_edits() > 0 && std::chrono::steady_clock::now() - t0 < kMaxWait)
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  return current_session_file();
}

// A session file's document on top of the session it opens (at the sync point, after the swap).
void Frontend::apply_session_edits(const SessionFile& f) {
  AppState& state = *session_.state;
  if (!f.path.empty()) state.request_path(f.path);
  const AppSnapshot snap = state.snapshot();
  for (std::size_t m = 0; m < snap.models.size(); ++m) {
    if (!f.params.contains(snap.models[m].id)) continue;
    ParamSet p = snap.models[m].params;
    p.update_from_json(f.params.at(snap.models[m].id), "session /params/" + snap.models[m].id);
    state.request_params(m, p);
  }
  state.request_seek(f.step);
  state.request_forget_history();  // the file's path and tables are where the user starts, not edits to undo
  workbench_.auto_scale_enabled() = f.auto_scale;
  if (f.arrow_gain > 0) workbench_.scale().arrow_gain = static_cast<float>(f.arrow_gain);
  if (f.colour_max_px > 0) workbench_.scale().colour_max_px = static_cast<float>(f.colour_max_px);
  if (f.camera) workbench_.set_camera_view(*f.camera);
  workbench_.read_display_choices(f);
  if (f.residual_file.empty()) {
    workbench_.clear_residual();
  } else {
    load_residual(f.residual_file);
    workbench_.set_residual_view(f.residual_fields, f.residual_corrected);
  }
}

void Frontend::apply_session_file(const SessionFile& f, Baseline baseline, std::function<void()> then) {
  SessionOptions o = session_options_;
  o.open = f.open;
  const std::string what = !f.open.dataset_dir.empty()  ? f.open.dataset_dir
                           : !f.open.scene_path.empty() ? f.open.scene_path
                                                        : std::string("the default scene");
  reopen_then(o, baseline, what, [this, f, then = std::move(then)] {
    apply_session_edits(f);
    if (then) then();
  });
}

void Frontend::open_session_file(const std::string& path, std::function<void()> then) {
  SessionFile f;
  try {
    f = load_session_file(path);
  } catch (...) {
    workbench_.revert_session_path();  // a failed open adopts nothing
    throw;
  }
  apply_session_file(f, Baseline::kClean, [this, path, then = std::move(then)] {
    keeper_.opened_session_file();
    workbench_.set_saved_once(true);
    workbench_.set_session_path(path);
    workbench_.set_message("opened session " + path);
    if (then) then();
  });
}

void Frontend::offer_autosave() {
  if (!keeper_.has_autosave()) return;
  workbench_.ask("restore",
                 "shearbench did not close cleanly last time.\nRestore the unsaved session autosaved in\n" +
                     keeper_.autosave_path() + " ?",
                 {"Restore", "Discard"});
}

void Frontend::handle_answer(const std::string& id, int button) {
  if (id == "restore") {
    if (button == 0) {
      apply_session_file(load_session_file(keeper_.autosave_path()), Baseline::kRestored,
                         [this] { workbench_.set_message("restored the autosaved session (not yet saved: Ctrl+S)"); });
    } else {
      keeper_.discard_autosave();
    }
  } else if (id == "close") {
    if (button == 0) {  // Save, then close (a refused path keeps the window open, with the reason)
      save_session_to(workbench_.session_path());
      keeper_.confirm_close();
      quit_ = true;
    } else if (button == 1) {  // Discard
      keeper_.confirm_close();
      quit_ = true;
    }
  }
}

void Frontend::update_window_title() {
  std::string state = loader_.pending()      ? "opening " + loader_.what()
                      : keeper_.dirty()      ? std::string("unsaved changes")
                      : keeper_.saved_once() ? std::string("saved")
                                             : std::string("new session, not saved");
  const std::string title = "shearbench - " + session_.title + " - " + state;
  if (title == window_title_) return;
  window_title_ = title;
  glfwSetWindowTitle(window_.handle(), title.c_str());
}

void Frontend::keep_work_tick() {
  const std::optional<WorkKeeper::Check> check = keeper_.tick(now_s());
  if (!check) return;
  workbench_.set_unsaved(check->dirty);
  if (!check->autosave_error.empty()) workbench_.set_message("autosave failed: " + check->autosave_error);
}

// Screenshots, exports, drags, scene and residual loads free what they allocated, but glibc keeps the freed
// pages: in the hour soak the heap (RssAnon) swung between 99 and 135 MB with a trim once a minute
// (docs/reliability.md). So the idle workbench hands them back every 10 s (a few ms, outside any measured frame).
void Frontend::trim_memory_when_idle() {
  constexpr double kTrimEveryS = 10.0;
  const double now = now_s();
  if (now - last_trim_s_ < kTrimEveryS || workbench_.animating()) return;
  last_trim_s_ = now;
  return_free_memory_to_os();
}

// Called when the user asked to close: with unsaved work, ask first (the window stays open).
bool Frontend::allow_close() {
  if (!options_.keep_work) return false;
  if (keeper_.unsaved_on_close(now_s())) {
    quit_ = false;
    glfwSetWindowShouldClose(window_.handle(), GLFW_FALSE);
    if (!workbench_.asking())
      workbench_.ask(
          "close", "There are unsaved changes.\nSave the session to " + workbench_.session_path() + " before closing?",
          {"Save", "Discard", "Cancel"});
    return true;
  }
  keeper_.discard_autosave();  // a clean exit: nothing to offer back next time
  return false;
}

ui::Image Frontend::render_still(int frames) {
  ui::Image img;
  for (int i = 0; i < frames; ++i) {
    window_.begin_frame();
    workbench_.draw(0.0);
    workbench_.wait_for_background();  // the RMSE series of a replay are in the image, complete
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
  constexpr double kRadiusM = 2.0e-3;  // circle radius of the synthetic drag
  constexpr double kTurnsPerFrame = 1.0 / 120.0;
  for (int i = 0; i < frames; ++i) {
    Pose X = pressed;
    const double a = 2 * M_PI * kTurnsPerFrame * i;
    X.translation().x() += kRadiusM * std::cos(a);
    X.translation().y() += kRadiusM * std::sin(a);
    state.request_drag(X);
    using clock = std::chrono::steady_clock;
    const auto ms_since = [](clock::time_point t) {
      return std::chrono::duration<double, std::milli>(clock::now() - t).count();
    };
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

}  // namespace sb::app
