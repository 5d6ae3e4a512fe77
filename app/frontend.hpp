#pragma once
// The frame loop both `gui` and `render` use: one window, one workbench, one session.
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/frame_report.hpp"
#include "app/session.hpp"
#include "app/session_loader.hpp"
#include "core/workbench/open_target.hpp"
#include "core/workbench/session_file.hpp"
#include "core/workbench/work_keeper.hpp"
#include "widgets/frame_stats.hpp"
#include "widgets/gl_window.hpp"
#include "widgets/workbench.hpp"

namespace sb::app {

// "FOTS (reimpl)" -> "fots_reimpl": a region name as part of a file name.
std::string file_slug(const std::string& text);

struct FrontendOptions {
  int width = 1280;
  int height = 800;
  bool visible = true;
  bool show_timings = true;
  bool interactive = true;
  std::string camera = "iso";  // iso | top | side
  // The interactive GUI keeps the user's work: autosave while dirty, offer it back after a crash,
  // ask before closing with unsaved changes. Off for headless renders.
  bool keep_work = false;
  std::string autosave_path;  // empty: default_autosave_path()
  double autosave_interval_s = 30.0;
  // Where P's screenshots and a relative field-export folder go (core/workbench/output_folder): empty: beside the
  // session file, or the per-user folder when that is in a checkout.
  std::string output_folder;
};

class Frontend {
 public:
  Frontend(const SessionOptions& session, const FrontendOptions& options);
  ~Frontend();
  // One frame: events, workbench, render, (screenshot), present. Returns false when the user quit.
  bool frame();
  // Draws `frames` frames without presenting the last, and returns its pixels (headless render).
  ui::Image render_still(int frames);
  // Frame times (ms) of `frames` frames while a synthetic drag moves the indenter (in contact) around
  // a circle in the pad plane with the physics on its thread; what "dragging the cow" costs.
  std::vector<double> profile_drag(int frames);
  Session& session() { return session_; }
  ui::Workbench& workbench() { return workbench_; }
  // How the clean/unsaved baseline follows a new session (core/workbench/work_keeper.hpp).
  using Baseline = WorkBaseline;
  // Opens `session` now (headless renders, tests).
  void reopen(const SessionOptions& session, Baseline baseline = Baseline::kClean);
  // The interactive GUI opens on a worker (core/base/status_job.hpp) while the window stays live with a
  // progress line; the new session is swapped in at the start of a frame (one sync point), then `then`
  // runs. Headless (not interactive): at once, as reopen. `what` names it in the progress line.
  void reopen_then(const SessionOptions& session, Baseline baseline, const std::string& what,
                   std::function<void()> then = {});
  bool loading() const { return loader_.pending(); }
  // A path typed into the Open field (or chosen from its list): dataset, scene or session file
  // (core/workbench/open_target.hpp); `from_session_field`: a failed open leaves the session path as it was.
  void open_path(const std::string& typed, bool from_session_field);
  // Session files (core/workbench/session_file.hpp): what the user made, saved and reopened.
  SessionFile current_session_file() const;
  // current_session_file() once the physics has applied every queued edit (bounded wait): what saves write.
  SessionFile session_file_for_saving();
  // Opens a session file (on the worker in the GUI); `then` runs once it is in place. A file that cannot be
  // read leaves the session path as it was (InputError).
  void open_session_file(const std::string& path, std::function<void()> then = {});
  // Every model's field along the current path as <dir>/<model id>/ (tsd/1), on the workbench's export
  // worker (core/workbench/field_export). start_export returns at once; InputError when a target folder exists
  // and is not an earlier export (checked before the worker starts). export_fields (headless renders)
  // also waits and returns how many were written; it throws when the export did not finish.
  void start_export(const std::string& dir);
  int export_fields(const std::string& dir);
  // The named region of the last drawn frame (ui::Workbench::regions) cut out of `image`.
  ui::Image crop_to_region(const ui::Image& image, const std::string& region) const;
  // Replaces a panel's model by another variant (fots | fots-reimpl, tacsl | tacsl-normalized).
  void set_beside_hydroshear(const std::string& model_id);  // "" removes the panel
  void switch_model(int slot, const std::string& model_id);
  // A residual analysis (shearbench residual --json) for the Residual section; throws InputError. False (and a
  // status line naming both) when the report is of another dataset than the open one: nothing is replaced.
  bool load_residual(const std::string& path);
  // The folder the workbench's files go to now (it follows the session file).
  std::string output_folder() const;
  // `gui --stats FILE`: a JSON line of frame times, memory and GL objects every interval_s (widgets/frame_stats).
  void enable_stats(const std::string& path, double interval_s) { stats_ = ui::FrameStats(path, interval_s); }
  // When an autosave from an unclean exit exists, asks whether to restore it.
  void offer_autosave();

 private:
  void handle(const ui::WorkbenchRequest& req, bool before_present);
  void handle_open_requests(const ui::WorkbenchRequest& req);
  // The unsaved work an open replaced: its document, the file Ctrl+S wrote it to, and its title.
  struct ReplacedWork {
    SessionFile file;
    std::string session_path;
    std::string title;
  };
  void keep_replaced_work();
  void bring_back_replaced_work();
  std::optional<ReplacedWork> replaced_work_;
  bool announce_replaced_work_ = false;  // the next "opened" line says the work is kept
  void save_session_to(const std::string& path);
  void install_session(Session next, const SessionOptions& options, Baseline baseline);
  void poll_load();
  void refresh_open_choices();
  // "shearbench - <what is open> - unsaved changes | new session, not saved | saved | opening ...": the state
  // a window manager (and tests/cli/gui_journeys.py, through xdotool) can read.
  void update_window_title();
  std::string window_title_;
  FieldExportRequest export_request(const std::string& dir) const;
  void handle_answer(const std::string& id, int button);
  void apply_session_file(const SessionFile& file, Baseline baseline, std::function<void()> then = {});
  void apply_session_edits(const SessionFile& file);
  void keep_work_tick();
  bool allow_close();
  std::string screenshot_region_;
  double now_s() const;
  SessionOptions session_options_;
  FrontendOptions options_;
  std::string output_folder_for_;  // the session path the Session tooltip's output folder was computed for
  Session session_;
  ui::GlWindow window_;
  ui::Workbench workbench_;
  double frame_ms_ = 0;
  ui::FrameStats stats_;
  bool quit_ = false;
  bool screenshot_pending_ = false;
  WorkKeeper keeper_;     // no lost work (keep_work)
  SessionLoader loader_;  // opening on a worker (reopen_then)
  RecentPaths recent_;
  double last_trim_s_ = 0;  // steady-clock seconds of the last trim_memory_when_idle
  void trim_memory_when_idle();
};

ui::CameraPreset parse_camera(const std::string& name);

}  // namespace sb::app
