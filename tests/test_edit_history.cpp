// EditHistory: undo/redo of the user's edits, alone and as AppState records and applies it at the sync point,
// tested without GL on a small history-dependent model (so a replay that skipped or repeated a step would show).
#include <catch2/catch.hpp>

#include "core/workbench/app_state.hpp"
#include "core/workbench/edit_history.hpp"

// This file's names in a namespace of its own: the unity build compiles several test files as one unit.
namespace test_edit_history {

using namespace sb;

namespace {

// After poses x_0..x_k (x = indenter x in metres): disp_px[0] = (sum_i gain * x_i * (i + 1), steps taken).
class WeightedSumModel final : public ShearModel {
 public:
  WeightedSumModel() : params_({{"gain", "", 1.0, 0.0, 100.0, "output scale"}}) {}
  std::string id() const override { return "weighted"; }
  const ParamSet& params() const override { return params_; }
  void set_params(const ParamSet& p) override { params_ = p; }
  void reset() override {
    acc_ = 0;
    steps_ = 0;
  }
  void step(const Pose& X_EI, double, FieldOutput* out) override {
    acc_ += params_.get("gain") * X_EI.translation().x() * double(steps_ + 1);
    ++steps_;
    out->disp_px = {Vec2(acc_, double(steps_))};
  }
  std::unique_ptr<ShearModel> clone() const override { return std::make_unique<WeightedSumModel>(*this); }

 private:
  ParamSet params_;
  double acc_ = 0;
  int steps_ = 0;
};

// x = 1, 2, ..., n mm.
std::vector<Pose> ramp_path(int n) {
  std::vector<Pose> path;
  for (int i = 0; i < n; ++i) path.push_back(make_pose(Vec3(0.001 * (i + 1), 0, 0), Quat::Identity()));
  return path;
}

std::unique_ptr<AppState> make_state(int n) {
  std::vector<std::unique_ptr<ShearModel>> models;
  models.push_back(std::make_unique<WeightedSumModel>());
  AppStateConfig config;
  config.checkpoint_every = 4;
  config.max_substep_translation_m = 0.25e-3;
  return std::make_unique<AppState>(nullptr, nullptr, std::move(models), ramp_path(n), 0.02, config);
}

ParamSet with_gain(const AppState& state, double gain) {
  ParamSet p = state.model(0).params();
  p.set("gain", gain);
  return p;
}

// A path entry's state: a path of n poses (x = 1..n mm) shown at step `step`.
PathEditState path_of(int n, int step) { return {std::make_shared<const std::vector<Pose>>(ramp_path(n)), step, n}; }
EditEntry path_edit(const std::string& label, int n_before, int n_after, std::uint64_t gesture = 0) {
  return {label, path_of(n_before, 0), path_of(n_after, n_after - 1), gesture};
}
std::size_t path_size(const EditState& s) { return std::get<PathEditState>(s).path->size(); }

// The fake model computes in doubles from the same operations in the same order: results are exact.
constexpr double kExact = 0.0;

}  // namespace

TEST_CASE("undo hands back the newest edit's before, redo its after", "[edit_history]") {
  EditHistory h;
  CHECK_FALSE(h.undo());
  h.record(path_edit("drag of the indenter", 75, 6));
  h.record(path_edit("nudge of the indenter", 6, 7));
  CHECK(h.undo_label() == "nudge of the indenter");
  auto u = h.undo();
  REQUIRE(u);
  CHECK(path_size(u->before) == 6u);
  CHECK(h.undo_label() == "drag of the indenter");
  CHECK(h.redo_label() == "nudge of the indenter");
  u = h.undo();
  REQUIRE(u);
  CHECK(path_size(u->before) == 75u);  // the scene's path is back
  CHECK_FALSE(h.undo());
  auto r = h.redo();
  REQUIRE(r);
  CHECK(path_size(r->after) == 6u);
  CHECK(h.undo_size() == 1u);
  CHECK(h.redo_size() == 1u);
}

TEST_CASE("a new edit after an undo clears the redo side", "[edit_history]") {
  EditHistory h;
  h.record(path_edit("a", 10, 11));
  h.record(path_edit("b", 11, 12));
  h.undo();
  REQUIRE(h.redo_size() == 1u);
  h.record(path_edit("c", 11, 13));
  CHECK(h.redo_size() == 0u);
  CHECK_FALSE(h.redo());
  CHECK(h.undo_label() == "c");
}

TEST_CASE("one gesture is one entry: its first before, its last after", "[edit_history]") {
  EditHistory h;
  // A drag's three mouse moves (gesture 7) grow the path 10 -> 11 -> 12 -> 13.
  h.record(path_edit("drag of the indenter", 10, 11, 7));
  h.record(path_edit("drag of the indenter", 11, 12, 7));
  h.record(path_edit("drag of the indenter", 12, 13, 7));
  REQUIRE(h.undo_size() == 1u);
  // The next gesture and a gesture-less edit are entries of their own.
  h.record(path_edit("drag of the indenter", 13, 14, 8));
  h.record(path_edit("nudge of the indenter", 14, 15));
  h.record(path_edit("nudge of the indenter", 15, 16));
  CHECK(h.undo_size() == 4u);
  h.undo();
  h.undo();
  h.undo();
  const auto u = h.undo();
  REQUIRE(u);
  CHECK(path_size(u->before) == 10u);
  CHECK(path_size(u->after) == 13u);
}

TEST_CASE("a gesture does not join another model's table nor a path", "[edit_history]") {
  EditHistory h;
  const ParamSet p({{"gain", "", 1.0, 0.0, 100.0, "output scale"}});
  h.record({"slider", ParamsEditState{0, p}, ParamsEditState{0, p}, 3});
  h.record({"slider", ParamsEditState{1, p}, ParamsEditState{1, p}, 3});
  h.record(path_edit("drag", 5, 6, 3));
  CHECK(h.undo_size() == 3u);
}

TEST_CASE("the history is bounded in entries and in stored poses, the newest kept", "[edit_history]") {
  constexpr std::size_t kCapacity = 3;
  EditHistory by_count(kCapacity);
  for (int i = 0; i < 5; ++i) by_count.record(path_edit(std::to_string(i), 2, 2));
  CHECK(by_count.undo_size() == kCapacity);
  CHECK(by_count.undo_label() == "4");
  // 100 poses at most: each entry keeps 20 + 20 poses, so two entries (80) fit and a third (120) does not.
  EditHistory by_poses(200, 100);
  for (int i = 0; i < 4; ++i) by_poses.record(path_edit(std::to_string(i), 20, 20));
  CHECK(by_poses.undo_size() == 2u);
  // One entry over the bound alone stays: the edit just made can always be undone.
  EditHistory tiny(200, 10);
  tiny.record(path_edit("big", 50, 50));
  CHECK(tiny.undo_size() == 1u);
  CHECK_THROWS(EditHistory(0));
}

TEST_CASE("a replaced model's tables leave the history", "[edit_history]") {
  EditHistory h;
  const ParamSet p({{"gain", "", 1.0, 0.0, 100.0, "output scale"}});
  h.record({"table of 0", ParamsEditState{0, p}, ParamsEditState{0, p}, 0});
  h.record(path_edit("drag", 5, 6));
  h.record({"table of 1", ParamsEditState{1, p}, ParamsEditState{1, p}, 0});
  h.undo();  // table of 1 on the redo side
  h.forget_model(1);
  CHECK(h.redo_size() == 0u);
  h.forget_model(0);
  CHECK(h.undo_size() == 1u);
  CHECK(h.undo_label() == "drag");
}

TEST_CASE("undo of a nudge at step 0 brings the path back, applied at the sync point", "[edit_history]") {
  auto state = make_state(75);
  state->request_seek(0);
  state->sync();
  // A nudge at step 0 (x = 1 mm) to x = 1.1 mm: the path becomes path[0] and ceil(0.1 / 0.25) = 1 sub-step.
  state->request_drag(make_pose(Vec3(0.0011, 0, 0), Quat::Identity()), {"nudge of the indenter", 0});
  state->sync();
  REQUIRE(state->path().size() == 2u);
  CHECK(state->snapshot().undo_label == "nudge of the indenter");
  while (state->tick()) {
  }
  REQUIRE(state->current_step() == 1);
  state->request_undo();
  CHECK(state->path().size() == 2u);  // queued, not applied before the sync point
  state->sync();
  CHECK(state->path().size() == 75u);
  const AppSnapshot s = state->snapshot();
  CHECK(s.step == 0);  // where the nudge was made
  CHECK(s.measured_steps == 75);
  CHECK(s.undo_label.empty());
  CHECK(s.redo_label == "nudge of the indenter");
  // At step 0 of the ramp: gain 1 * x_0 1 mm * weight 1 = 0.001.
  CHECK(s.models[0].out.disp_px[0].x() == Approx(0.001).margin(kExact));
  // Redo: the nudged path again, shown at the dragged pose (its last step, 1).
  state->request_redo();
  state->sync();
  CHECK(state->path().size() == 2u);
  CHECK(state->current_step() == 1);
  // 0.001 * 1 + 0.0011 * 2 = 0.0032.
  CHECK(state->snapshot().models[0].out.disp_px[0].x() == Approx(0.0032).margin(1e-15));
}

TEST_CASE("one drag of several mouse moves is one undo entry", "[edit_history]") {
  auto state = make_state(10);
  state->request_seek(3);
  state->sync();
  const std::uint64_t gesture = state->new_gesture();
  for (int move = 1; move <= 3; ++move) {
    state->request_drag(make_pose(Vec3(0.004 + 0.0005 * move, 0, 0), Quat::Identity()), {"", gesture});
    state->tick();  // the physics catches up between mouse moves
  }
  while (state->tick()) {
  }
  CHECK(state->snapshot().undo_label == "drag of the indenter");
  state->request_undo();
  state->sync();
  CHECK(state->path().size() == 10u);
  CHECK(state->current_step() == 3);
  CHECK(state->snapshot().undo_label.empty());  // one entry, and it was undone
}

TEST_CASE("undo of a parameter edit replays the old table to the current step", "[edit_history]") {
  auto state = make_state(10);
  state->request_seek(2);
  state->sync();
  const std::uint64_t gesture = state->new_gesture();
  for (double gain : {2.0, 3.0, 4.0}) {  // one slider drag over three frames
    state->request_params(0, with_gain(*state, gain), {"", gesture});
    state->sync();
  }
  CHECK(state->model(0).params().get("gain") == 4.0);
  CHECK(state->snapshot().undo_label == "parameters of weighted");
  state->request_undo();
  state->sync();
  CHECK(state->model(0).params().get("gain") == 1.0);
  // Step 2 at gain 1: 1 * (0.001 * 1 + 0.002 * 2 + 0.003 * 3) = 0.014.
  CHECK(state->snapshot().models[0].out.disp_px[0].x() == Approx(0.014).margin(1e-15));
  state->request_redo();
  state->sync();
  CHECK(state->model(0).params().get("gain") == 4.0);
}

TEST_CASE("a replaced path is undoable; forgotten edits are not", "[edit_history]") {
  auto state = make_state(10);
  state->request_path(ramp_path(4));
  state->sync();
  CHECK(state->snapshot().undo_label == "replaced path");
  state->request_undo();
  state->sync();
  CHECK(state->path().size() == 10u);
  // A session file's path and tables are where the user starts: nothing to undo after them.
  state->request_path(ramp_path(4));
  state->request_params(0, with_gain(*state, 5.0));
  state->request_forget_history();
  state->sync();
  CHECK(state->snapshot().undo_label.empty());
  CHECK(state->snapshot().redo_label.empty());
  state->request_undo();
  state->sync();
  CHECK(state->path().size() == 4u);
}

}  // namespace test_edit_history
