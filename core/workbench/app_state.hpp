#pragma once
// The workbench's one owner of simulation state (MuJoCo-simulate style): the sensor, the indenter, one
// ShearModel per id with its ParamSet, the pose path X_EI(0..n-1), the current step, every model's
// FieldOutput of that step and per-step timings.
//
// Two sides:
//  - the UI side only *requests* edits (parameter change, seek, drag, play/pause) and reads a copied
//    snapshot; both are short critical sections, so drawing never waits for a model step;
//  - the physics side (one thread, or the caller in headless use) calls sync() — the one place where
//    queued edits are applied, in order, exactly once — and step() between syncs.
//
// Step numbering: step k means the models have consumed path[0..k]; step -1 is before the first pose.
// Seeks restore the nearest per-model checkpoint (a clone() every `checkpoint_every` steps) and step
// forward, so seeking to k gives the same outputs as stepping from 0 to k. A parameter change resets
// that model and replays it from the start to the current step. A drag replaces the path after the
// current step by a sub-stepped segment to the dragged pose, so a fast drag never skips contact.
// Every path and parameter edit applied is recorded in an undo history (core/workbench/edit_history.hpp);
// undo and redo are edits too, queued and applied at the sync point.
// This file includes no GL; it is tested in tests/test_app_state.cpp.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "core/geometry/indenter.hpp"
#include "core/models/model.hpp"
#include "core/sensor/sensor.hpp"
#include "core/workbench/edit_history.hpp"

namespace sb {

struct AppStateConfig {
  int checkpoint_every = 16;                   // steps between model clones (seek cost <= this many steps)
  double max_substep_translation_m = 0.25e-3;  // a drag moves at most this far per model step ...
  double max_substep_rotation_rad = 0.035;     // ... and turns at most this much (2 degrees)
};

struct StepTiming {
  double last_ms = 0;
  double mean_ms = 0;  // exponential mean over recent steps
  long count = 0;
};

struct ModelView {
  std::string id;
  ParamSet params;
  FieldOutput out;
  StepTiming timing;
};

// What the UI draws: a copy, consistent (all models at the same step).
struct AppSnapshot {
  int step = -1;
  int num_steps = 0;             // path length
  int measured_steps = 0;        // steps [0, measured_steps) still follow the original (dataset) path
  Pose X_EI = Pose::Identity();  // pose at `step` (path[0] before the first step)
  double dt_s = 0.02;
  bool playing = false;
  double speed = 1.0;
  std::vector<ModelView> models;
  std::uint64_t version = 0;  // bumps on every published change
  std::string undo_label;     // what an undo would take back ("" when nothing): "drag of the indenter"
  std::string redo_label;
};

// Which user action an edit comes from, for the undo history: its name there ("" for the edit's own:
// "drag of the indenter", "parameters of <model id>", "replaced path") and the gesture it belongs to
// (AppState::new_gesture(); 0: an edit of its own). Every edit of one gesture is one undo entry.
struct EditOrigin {
  std::string label;
  std::uint64_t gesture = 0;
};

// Linear interpolation in position, slerp in rotation; t in [0, 1].
Pose interpolate_pose(const Pose& a, const Pose& b, double t);
// The poses strictly after `from` up to and including `to`, enough of them that consecutive poses differ
// by at most max_translation_m and max_rotation_rad (at least one: `to`).
std::vector<Pose> substep_path(const Pose& from, const Pose& to, double max_translation_m, double max_rotation_rad);

class AppState {
 public:
  AppState(std::shared_ptr<const Sensor> sensor, std::shared_ptr<const Indenter> indenter,
           std::vector<std::unique_ptr<ShearModel>> models, std::vector<Pose> path, double dt_s,
           AppStateConfig config = {});
  ~AppState();
  AppState(const AppState&) = delete;
  AppState& operator=(const AppState&) = delete;

  // ---- UI side (thread-safe; never runs a model)
  void request_params(std::size_t model, const ParamSet& params, EditOrigin origin = {});
  void request_seek(int step);
  void request_drag(const Pose& X_EI_target, EditOrigin origin = {});
  // Replaces the path (e.g. another sample) and rewinds.
  void request_path(std::vector<Pose> path, EditOrigin origin = {});
  // Undo the newest recorded edit / redo the one undone last (nothing when there is none): the path comes
  // back with the step it was at, a parameter table replays the model to the current step.
  void request_undo();
  void request_redo();
  // The edits queued so far are where the user starts (a session file's path and tables), not theirs to undo.
  void request_forget_history();
  // A fresh gesture id for EditOrigin (never 0).
  std::uint64_t new_gesture() { return ++last_gesture_; }
  // Replaces one slot's model (e.g. FOTS by FOTS re-impl.): the new model replays the path up to the
  // current step, so its field is consistent with the history; the other slots are untouched.
  void request_model(std::size_t slot, std::unique_ptr<ShearModel> model);
  void set_playing(bool playing);
  void set_speed(double speed);
  AppSnapshot snapshot() const;
  std::uint64_t version() const { return version_.load(); }
  // Edits queued or being applied: 0 once every edit requested so far is visible in snapshot().
  std::size_t pending_edits() const;

  // ---- physics side (one thread at a time)
  // The sync point: applies every queued edit once, in the order queued (of several parameter tables
  // for one model in a batch only the last is applied: each replaces the whole table). Returns how many
  // edits were taken from the queue.
  int sync();
  // Advances every model one step along the path; false when already at its end.
  bool step();
  // One loop iteration: sync(), then step() when playing or while a drag segment is pending.
  bool tick();
  // Headless use: sync, seek to `step`, publish.
  void run_to(int step);

  int current_step() const { return step_; }
  // A copy: the physics thread appends to the path while a drag is applied.
  std::vector<Pose> path() const;
  std::size_t num_models() const { return slots_.size(); }
  const FieldOutput& output(std::size_t model) const { return slots_.at(model).out; }
  const ShearModel& model(std::size_t model) const { return *slots_.at(model).model; }
  std::shared_ptr<const Sensor> sensor() const { return sensor_; }
  std::shared_ptr<const Indenter> indenter() const { return indenter_; }
  double dt_s() const { return dt_s_; }

  // Runs tick() on a background thread, pacing play-back at dt / speed of wall time and running drag
  // segments and seeks as fast as the models go.
  void start_thread();
  void stop_thread();
  // Called (on the physics thread) after each publish: lets a GUI sleeping in its event wait wake up.
  void set_on_publish(std::function<void()> fn) { on_publish_ = std::move(fn); }

 private:
  struct SetParams {
    std::size_t model;
    ParamSet params;
    EditOrigin origin;
  };
  struct Seek {
    int step;
  };
  struct Drag {
    Pose target;
    EditOrigin origin;
  };
  struct ReplacePath {
    std::vector<Pose> path;
    EditOrigin origin;
  };
  struct Undo {};
  struct Redo {};
  struct ForgetHistory {};
  struct ReplaceModel {
    std::size_t model;
    std::shared_ptr<ShearModel> replacement;
  };
  using Edit = std::variant<SetParams, Seek, Drag, ReplacePath, ReplaceModel, Undo, Redo, ForgetHistory>;

  struct Checkpoint {
    std::unique_ptr<ShearModel> model;  // the state after that step (a seek steps on from it)
  };
  struct Slot {
    std::unique_ptr<ShearModel> model;
    FieldOutput out;
    StepTiming timing;
    std::map<int, Checkpoint> checkpoints;  // step -> state after that step (-1: fresh)
  };

  void apply(const SetParams& e);
  void apply(const Seek& e);
  void apply(const Drag& e);
  void apply(const ReplacePath& e);
  void apply(const ReplaceModel& e);
  void apply(const Undo& e);
  void apply(const Redo& e);
  void apply(const ForgetHistory& e);
  void push_edit(Edit e);
  // The path as an undo entry keeps it; `step`: the step it is shown at.
  PathEditState path_state(int step) const;
  void restore(const EditState& s);
  void restore_path(const PathEditState& s);
  void restore_params(const ParamsEditState& s);
  void step_slot(Slot& slot, int k);
  void rewind_slot(Slot& slot);
  void seek_slot(Slot& slot, int target);
  void drop_checkpoints_after(int step);
  void publish();

  std::shared_ptr<const Sensor> sensor_;
  std::shared_ptr<const Indenter> indenter_;
  AppStateConfig config_;
  double dt_s_;

  // physics side
  std::vector<Slot> slots_;
  std::vector<Pose> path_;  // written by the physics thread only, under path_mutex_
  mutable std::mutex path_mutex_;
  int step_ = -1;
  int measured_steps_ = 0;
  bool drag_active_ = false;
  EditHistory history_;

  // shared
  mutable std::mutex edits_mutex_;
  std::vector<Edit> edits_;
  std::size_t edits_in_flight_ = 0;  // taken from the queue by sync(), not yet published (edits_mutex_)
  mutable std::mutex snapshot_mutex_;
  AppSnapshot snapshot_;
  std::atomic<std::uint64_t> version_{0};
  std::atomic<bool> playing_{false};
  std::atomic<double> speed_{1.0};
  std::atomic<std::uint64_t> last_gesture_{0};

  std::function<void()> on_publish_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::condition_variable wake_;
  std::mutex wake_mutex_;
};

}  // namespace sb
