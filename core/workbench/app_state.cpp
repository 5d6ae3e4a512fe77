#include "core/workbench/app_state.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

namespace sb {

namespace {
// Weight of the newest step in StepTiming::mean_ms.
constexpr double kTimingSmoothing = 0.1;
// Background thread: how long to sleep when there is nothing to do (woken early by any request).
constexpr auto kIdleWait = std::chrono::milliseconds(20);
}  // namespace

Pose interpolate_pose(const Pose& a, const Pose& b, double t) {
  const Quat qa(a.linear()), qb(b.linear());
  return make_pose(a.translation() + t * (b.translation() - a.translation()), qa.slerp(t, qb));
}

std::vector<Pose> substep_path(const Pose& from, const Pose& to, double max_translation_m, double max_rotation_rad) {
  const double distance = (to.translation() - from.translation()).norm();
  const double angle = Quat(from.linear()).angularDistance(Quat(to.linear()));
  // The slack keeps an exact multiple of the limit (2 mm at 0.25 mm) from rounding up to one more step.
  constexpr double kSlack = 1e-9;
  const int n = std::max({1, static_cast<int>(std::ceil(distance / max_translation_m - kSlack)),
                          static_cast<int>(std::ceil(angle / max_rotation_rad - kSlack))});
  std::vector<Pose> poses;
  poses.reserve(n);
  for (int i = 1; i <= n; ++i) poses.push_back(i == n ? to : interpolate_pose(from, to, double(i) / n));
  return poses;
}

AppState::AppState(std::shared_ptr<const Sensor> sensor, std::shared_ptr<const Indenter> indenter,
                   std::vector<std::unique_ptr<ShearModel>> models, std::vector<Pose> path, double dt_s,
                   AppStateConfig config)
    : sensor_(std::move(sensor)), indenter_(std::move(indenter)), config_(config), dt_s_(dt_s), path_(std::move(path)) {
  if (config_.checkpoint_every < 1) throw std::invalid_argument("AppState: checkpoint_every must be >= 1");
  measured_steps_ = static_cast<int>(path_.size());
  for (auto& m : models) {
    Slot s;
    s.model = std::move(m);
    rewind_slot(s);
    slots_.push_back(std::move(s));
  }
  publish();
}

AppState::~AppState() { stop_thread(); }

// ---------------------------------------------------------------- UI side
void AppState::push_edit(Edit e) {
  {
    std::lock_guard lock(edits_mutex_);
    edits_.push_back(std::move(e));
  }
  wake_.notify_one();
}
void AppState::request_params(std::size_t model, const ParamSet& params, EditOrigin origin) {
  if (model >= slots_.size()) throw std::out_of_range("AppState: no model " + std::to_string(model));
  push_edit(SetParams{model, params, std::move(origin)});
}
void AppState::request_seek(int step) { push_edit(Seek{step}); }
void AppState::request_drag(const Pose& X_EI_target, EditOrigin origin) {
  if (!is_finite(X_EI_target)) throw std::invalid_argument("AppState: non-finite drag pose");
  push_edit(Drag{X_EI_target, std::move(origin)});
}
void AppState::request_path(std::vector<Pose> path, EditOrigin origin) {
  push_edit(ReplacePath{std::move(path), std::move(origin)});
}
void AppState::request_undo() { push_edit(Undo{}); }
void AppState::request_redo() { push_edit(Redo{}); }
void AppState::request_forget_history() { push_edit(ForgetHistory{}); }
void AppState::request_model(std::size_t slot, std::unique_ptr<ShearModel> model) {
  if (slot >= slots_.size()) throw std::out_of_range("AppState: no model " + std::to_string(slot));
  if (!model) throw std::invalid_argument("AppState: null model");
  push_edit(ReplaceModel{slot, std::move(model)});
}
void AppState::set_playing(bool playing) {
  playing_ = playing;
  {
    std::lock_guard lock(snapshot_mutex_);
    snapshot_.playing = playing;
  }
  wake_.notify_one();
}
void AppState::set_speed(double speed) {
  speed_ = std::clamp(speed, 0.01, 100.0);
  std::lock_guard lock(snapshot_mutex_);
  snapshot_.speed = speed_;
}
AppSnapshot AppState::snapshot() const {
  std::lock_guard lock(snapshot_mutex_);
  return snapshot_;
}
std::size_t AppState::pending_edits() const {
  std::lock_guard lock(edits_mutex_);
  return edits_.size() + edits_in_flight_;
}
std::vector<Pose> AppState::path() const {
  std::lock_guard lock(path_mutex_);
  return path_;
}

// ---------------------------------------------------------------- physics side
int AppState::sync() {
  std::vector<Edit> edits;
  {
    std::lock_guard lock(edits_mutex_);
    edits.swap(edits_);
    edits_in_flight_ = edits.size();
  }
  for (std::size_t i = 0; i < edits.size(); ++i) {
    // A parameter set replaces the whole table and replays from the start: when the same model gets a
    // newer table later in this batch (a slider being dragged), only the last one needs the replay.
    if (const auto* p = std::get_if<SetParams>(&edits[i])) {
      const bool superseded = std::any_of(edits.begin() + i + 1, edits.end(), [&](const Edit& later) {
        const auto* q = std::get_if<SetParams>(&later);
        return q != nullptr && q->model == p->model;
      });
      if (superseded) continue;
    }
    std::visit([this](const auto& x) { apply(x); }, edits[i]);
  }
  if (!edits.empty()) publish();
  {
    std::lock_guard lock(edits_mutex_);
    edits_in_flight_ = 0;
  }
  return static_cast<int>(edits.size());
}

bool AppState::step() {
  if (step_ + 1 >= static_cast<int>(path_.size())) return false;
  ++step_;
  for (Slot& s : slots_) step_slot(s, step_);
  publish();
  return true;
}

bool AppState::tick() {
  sync();
  const bool more = step_ + 1 < static_cast<int>(path_.size());
  if (!more) {
    drag_active_ = false;
    if (playing_) set_playing(false);
    return false;
  }
  if (!playing_ && !drag_active_) return false;
  return step();
}

void AppState::run_to(int step) {
  sync();
  apply(Seek{step});
  publish();
}

void AppState::step_slot(Slot& slot, int k) {
  const auto t0 = std::chrono::steady_clock::now();
  slot.model->step(path_[k], dt_s_, &slot.out);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  StepTiming& t = slot.timing;
  t.last_ms = ms;
  t.mean_ms = t.count == 0 ? ms : (1 - kTimingSmoothing) * t.mean_ms + kTimingSmoothing * ms;
  ++t.count;
  if ((k + 1) % config_.checkpoint_every == 0) slot.checkpoints[k] = Checkpoint{slot.model->clone()};
}

void AppState::rewind_slot(Slot& slot) {
  slot.model->reset();
  slot.out = FieldOutput{};
  slot.checkpoints.clear();
  slot.checkpoints[-1] = Checkpoint{slot.model->clone()};
}

// From the last checkpoint before the target (never at it, so the target's output, diagnostics included, is
// always stepped afresh and a checkpoint keeps only the model's state: a path of thousands of steps costs
// O(contact) per checkpoint, not a field output with every contact point; docs/reliability.md).
void AppState::seek_slot(Slot& slot, int target) {
  auto it = slot.checkpoints.lower_bound(target);  // first checkpoint at or after target; -1 always exists
  if (it != slot.checkpoints.begin()) --it;
  slot.model = it->second.model->clone();
  slot.out = FieldOutput{};
  for (int k = it->first + 1; k <= target; ++k) step_slot(slot, k);
}

void AppState::drop_checkpoints_after(int step) {
  for (Slot& s : slots_) s.checkpoints.erase(s.checkpoints.upper_bound(step), s.checkpoints.end());
}

void AppState::apply(const SetParams& e) {
  ParamsEditState before{e.model, slots_.at(e.model).model->params()};
  restore_params({e.model, e.params});
  const ShearModel& model = *slots_.at(e.model).model;
  const std::string label = e.origin.label.empty() ? "parameters of " + model.id() : e.origin.label;
  history_.record({label, std::move(before), ParamsEditState{e.model, model.params()}, e.origin.gesture});
}

void AppState::apply(const Seek& e) {
  drag_active_ = false;
  const int target = std::clamp(e.step, -1, static_cast<int>(path_.size()) - 1);
  if (target == step_) return;
  for (Slot& s : slots_) {
    // Stepping forward from the current state is cheaper than restoring when the target is close ahead.
    if (target > step_ && target - step_ <= config_.checkpoint_every)
      for (int k = step_ + 1; k <= target; ++k) step_slot(s, k);
    else
      seek_slot(s, target);
  }
  step_ = target;
}

void AppState::apply(const Drag& e) {
  PathEditState before = path_state(step_);
  if (!drag_active_) {
    // The first drag of a gesture replaces the future of the path by the dragged segment.
    std::lock_guard lock(path_mutex_);
    const int kept_steps = step_ + 1;  // step_ >= -1
    path_.resize(static_cast<std::size_t>(kept_steps));
    drop_checkpoints_after(step_);
    measured_steps_ = std::min(measured_steps_, step_ + 1);
    drag_active_ = true;
  }
  const Pose from = path_.empty() ? e.target : path_.back();
  const std::vector<Pose> segment =
      substep_path(from, e.target, config_.max_substep_translation_m, config_.max_substep_rotation_rad);
  {
    std::lock_guard lock(path_mutex_);
    path_.insert(path_.end(), segment.begin(), segment.end());
  }
  // Redone, a drag shows where it ended: the dragged pose.
  history_.record({e.origin.label.empty() ? "drag of the indenter" : e.origin.label, std::move(before),
                   path_state(static_cast<int>(path_.size()) - 1), e.origin.gesture});
}

void AppState::apply(const ReplacePath& e) {
  PathEditState before = path_state(step_);
  drag_active_ = false;
  {
    std::lock_guard lock(path_mutex_);
    path_ = e.path;
  }
  measured_steps_ = static_cast<int>(path_.size());
  step_ = -1;
  for (Slot& s : slots_) rewind_slot(s);
  history_.record({e.origin.label.empty() ? "replaced path" : e.origin.label, std::move(before), path_state(step_),
                   e.origin.gesture});
}

void AppState::apply(const ReplaceModel& e) {
  Slot& slot = slots_.at(e.model);
  slot.model = e.replacement->clone();
  slot.timing = StepTiming{};
  rewind_slot(slot);
  for (int k = 0; k <= step_; ++k) step_slot(slot, k);
  history_.forget_model(e.model);  // the old model's tables do not fit the new one
}

void AppState::apply(const Undo& /*e*/) {
  if (auto entry = history_.undo()) restore(entry->before);
}
void AppState::apply(const Redo& /*e*/) {
  if (auto entry = history_.redo()) restore(entry->after);
}
void AppState::apply(const ForgetHistory& /*e*/) { history_.clear(); }

PathEditState AppState::path_state(int step) const {
  return {std::make_shared<const std::vector<Pose>>(path_), step, measured_steps_};
}

void AppState::restore(const EditState& s) {
  if (const auto* p = std::get_if<PathEditState>(&s))
    restore_path(*p);
  else
    restore_params(std::get<ParamsEditState>(s));
}

void AppState::restore_path(const PathEditState& s) {
  drag_active_ = false;
  const std::vector<Pose>& next = *s.path;
  // The checkpoints up to the last step both paths share stay valid; a seek restores from them.
  std::size_t shared = 0;
  {
    std::lock_guard lock(path_mutex_);
    while (shared < std::min(path_.size(), next.size()) && path_[shared].matrix() == next[shared].matrix()) ++shared;
    path_ = next;
  }
  measured_steps_ = s.measured_steps;
  drop_checkpoints_after(static_cast<int>(shared) - 1);
  const int target = std::clamp(s.step, -1, static_cast<int>(path_.size()) - 1);
  for (Slot& slot : slots_) seek_slot(slot, target);
  step_ = target;
}

// A parameter table replaces the model's and replays it from the start to the current step.
void AppState::restore_params(const ParamsEditState& s) {
  Slot& slot = slots_.at(s.model);
  slot.model->set_params(s.params);
  rewind_slot(slot);
  for (int k = 0; k <= step_; ++k) step_slot(slot, k);
}

void AppState::publish() {
  AppSnapshot s;
  s.step = step_;
  s.num_steps = static_cast<int>(path_.size());
  s.measured_steps = measured_steps_;
  if (!path_.empty()) s.X_EI = path_[std::max(step_, 0)];
  s.dt_s = dt_s_;
  s.playing = playing_;
  s.speed = speed_;
  s.models.reserve(slots_.size());
  for (const Slot& slot : slots_) s.models.push_back({slot.model->id(), slot.model->params(), slot.out, slot.timing});
  s.undo_label = history_.undo_label();
  s.redo_label = history_.redo_label();
  s.version = ++version_;
  {
    std::lock_guard lock(snapshot_mutex_);
    snapshot_ = std::move(s);
  }
  if (on_publish_) on_publish_();
}

// ---------------------------------------------------------------- background thread
void AppState::start_thread() {
  if (thread_.joinable()) return;
  stop_ = false;
  thread_ = std::thread([this] {
    auto next_play = std::chrono::steady_clock::now();
    while (!stop_) {
      const bool dragging_before = drag_active_;
      const bool stepped = tick();
      if (stepped && playing_ && !dragging_before) {
        // Play-back is paced to dt / speed of wall time; drag segments and seeks run flat out.
        next_play += std::chrono::duration_cast<std::chrono::steady_clock::duration>(
            std::chrono::duration<double>(dt_s_ / speed_));
        const auto now = std::chrono::steady_clock::now();
        if (next_play < now) next_play = now;
        std::unique_lock lock(wake_mutex_);
        wake_.wait_until(lock, next_play, [this] { return stop_.load() || pending_edits() > 0; });
      } else if (!stepped) {
        next_play = std::chrono::steady_clock::now();
        std::unique_lock lock(wake_mutex_);
        wake_.wait_for(lock, kIdleWait, [this] { return stop_.load() || pending_edits() > 0; });
      }
    }
  });
}

void AppState::stop_thread() {
  if (!thread_.joinable()) return;
  stop_ = true;
  wake_.notify_all();
  thread_.join();
}

}  // namespace sb
