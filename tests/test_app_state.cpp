// AppState: the workbench's sync point, seeks, parameter replays and drag sub-stepping, tested without GL
// on a small history-dependent model (so a replay that skipped or repeated a step would show).
#include <catch2/catch.hpp>
#include <cmath>

#include "core/workbench/app_state.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_app_state {

using namespace sb;

namespace {

// Its output depends on the whole pose history: after poses x_0..x_k (x = indenter x in metres),
//   acc_k = sum_i gain * x_i * (i + 1)   and   disp_px[0] = (acc_k, number of steps taken).
// Weighting by (i + 1) makes the order of steps matter, not just their sum.
class HistoryModel final : public ShearModel {
 public:
  HistoryModel() : params_({{"gain", "", 1.0, 0.0, 100.0, "output scale"}}) {}
  std::string id() const override { return "history"; }
  const ParamSet& params() const override { return params_; }
  void set_params(const ParamSet& p) override {
    params_ = p;
    ++set_params_calls;
  }
  void reset() override {
    acc_ = 0;
    steps_ = 0;
  }
  void step(const Pose& X_EI, double, FieldOutput* out) override {
    acc_ += params_.get("gain") * X_EI.translation().x() * double(steps_ + 1);
    ++steps_;
    poses.push_back(X_EI);
    out->disp_px = {Vec2(acc_, double(steps_))};
  }
  std::unique_ptr<ShearModel> clone() const override { return std::make_unique<HistoryModel>(*this); }

  int set_params_calls = 0;
  std::vector<Pose> poses;  // every pose this instance (and the instance it was cloned from) stepped

 private:
  ParamSet params_;
  double acc_ = 0;
  int steps_ = 0;
};

std::vector<Pose> ramp_path(int n) {
  std::vector<Pose> path;
  for (int i = 0; i < n; ++i) path.push_back(make_pose(Vec3(0.001 * (i + 1), 0, 0), Quat::Identity()));
  return path;
}

// Output of a fresh model stepped along path[0..k] with the given gain.
Vec2 direct_output(const std::vector<Pose>& path, int k, double gain) {
  HistoryModel m;
  ParamSet p = m.params();
  p.set("gain", gain);
  m.set_params(p);
  FieldOutput out;
  for (int i = 0; i <= k; ++i) m.step(path[i], 0.02, &out);
  return out.disp_px[0];
}

std::unique_ptr<AppState> make_state(int n, int checkpoint_every = 4) {
  std::vector<std::unique_ptr<ShearModel>> models;
  models.push_back(std::make_unique<HistoryModel>());
  models.push_back(std::make_unique<HistoryModel>());
  AppStateConfig config;
  config.checkpoint_every = checkpoint_every;
  config.max_substep_translation_m = 0.25e-3;
  return std::make_unique<AppState>(nullptr, nullptr, std::move(models), ramp_path(n), 0.02, config);
}

// The fake model computes in doubles from the same operations in the same order: results are exact.
constexpr double kExact = 0.0;

}  // namespace

TEST_CASE("queued edits are applied at the sync point, exactly once", "[ui]") {
  auto state = make_state(10);
  for (int i = 0; i < 3; ++i) state->step();
  ParamSet p = state->model(0).params();
  p.set("gain", 2.0);
  state->request_params(0, p);
  // Not applied until the sync point: stepping alone ignores the queue.
  state->step();
  CHECK(state->model(0).params().get("gain") == 1.0);
  CHECK(state->pending_edits() == 1);
  CHECK(state->sync() == 1);
  CHECK(state->pending_edits() == 0);
  CHECK(state->model(0).params().get("gain") == 2.0);
  // A second sync finds nothing: the edit is not applied twice (one set_params per model instance).
  CHECK(state->sync() == 0);
  CHECK(dynamic_cast<const HistoryModel&>(state->model(0)).set_params_calls == 1);
  // The other model is untouched.
  CHECK(state->model(1).params().get("gain") == 1.0);
}

TEST_CASE("seeking to step k gives what stepping from 0 to k gives", "[ui]") {
  const int n = 23;
  auto state = make_state(n, /*checkpoint_every=*/4);
  const auto path = state->path();
  // Walk to the end, then seek backwards and forwards across checkpoints (4, 8, ...) and between them.
  while (state->step()) {
  }
  for (int k : {17, 3, 0, -1, 9, 22, 11, 12, 5}) {
    state->request_seek(k);
    state->sync();
    REQUIRE(state->current_step() == k);
    for (std::size_t m = 0; m < state->num_models(); ++m) {
      if (k < 0) {
        CHECK(state->output(m).disp_px.empty());
        continue;
      }
      const Vec2 expected = direct_output(path, k, 1.0);
      CHECK(std::abs(state->output(m).disp_px[0].x() - expected.x()) <= kExact);
      CHECK(state->output(m).disp_px[0].y() == k + 1);  // exactly k + 1 steps in its history
    }
  }
  // Seeking beyond the path clamps to its last step.
  state->request_seek(1000);
  state->sync();
  CHECK(state->current_step() == n - 1);
}

TEST_CASE("a parameter change replays the model from the start to the current step", "[ui]") {
  auto state = make_state(12, 4);
  const auto path = state->path();
  for (int i = 0; i < 7; ++i) state->step();  // at step 6
  ParamSet p = state->model(1).params();
  p.set("gain", 3.0);
  state->request_params(1, p);
  state->sync();
  CHECK(state->current_step() == 6);
  CHECK(state->output(1).disp_px[0].x() == direct_output(path, 6, 3.0).x());
  CHECK(state->output(1).disp_px[0].y() == 7);
  CHECK(state->output(0).disp_px[0].x() == direct_output(path, 6, 1.0).x());
  // Checkpoints made before the change are gone: seeking back uses the new parameters.
  state->request_seek(4);
  state->sync();
  CHECK(state->output(1).disp_px[0].x() == direct_output(path, 4, 3.0).x());
}

TEST_CASE("a drag is sub-stepped so that no model step moves more than the limit", "[ui]") {
  auto state = make_state(5, 4);
  state->step();
  state->step();  // at step 1, pose x = 2 mm
  // Drag 2 mm further in x: with a 0.25 mm limit that is ceil(2 / 0.25) = 8 sub-steps.
  const Pose target = make_pose(Vec3(0.004, 0, 0), Quat::Identity());
  state->request_drag(target);
  state->sync();
  REQUIRE(state->path().size() == 2u + 8u);  // the rest of the original path is replaced
  state->request_drag(make_pose(Vec3(0.004, 0, 0), Quat(Eigen::AngleAxisd(0.1, Vec3::UnitZ()))));
  state->sync();
  // 0.1 rad twist at <= 0.035 rad per sub-step: ceil(0.1 / 0.035) = 3 more poses.
  REQUIRE(state->path().size() == 2u + 8u + 3u);
  // The drag makes the physics advance without play: tick() runs the whole segment.
  while (state->tick()) {
  }
  CHECK(state->current_step() == 12);
  const auto& stepped = dynamic_cast<const HistoryModel&>(state->model(0)).poses;
  constexpr double kLimitSlack = 1e-12;               // rounding in the interpolation
  for (std::size_t i = 2; i < stepped.size(); ++i) {  // 0, 1: the original 1 mm ramp
    CHECK((stepped[i].translation() - stepped[i - 1].translation()).norm() <= 0.25e-3 + kLimitSlack);
    CHECK(Quat(stepped[i].linear()).angularDistance(Quat(stepped[i - 1].linear())) <= 0.035 + kLimitSlack);
  }
  CHECK(stepped.back().isApprox(state->path().back()));
  // The dataset's measurements only apply to the steps before the drag.
  CHECK(state->snapshot().measured_steps == 2);
}

TEST_CASE("the snapshot is a consistent copy of one step", "[ui]") {
  auto state = make_state(6);
  const auto v0 = state->snapshot().version;
  state->step();
  state->step();
  const AppSnapshot s = state->snapshot();
  CHECK(s.version > v0);
  CHECK(s.step == 1);
  CHECK(s.num_steps == 6);
  REQUIRE(s.models.size() == 2);
  CHECK(s.models[0].out.disp_px[0].y() == 2);
  CHECK(s.models[1].out.disp_px[0].y() == 2);
  CHECK(s.X_EI.translation().x() == Approx(0.002));
}

TEST_CASE("the background thread plays the path and stops at its end", "[ui]") {
  auto state = make_state(8);
  state->set_speed(100.0);  // dt 0.02 s at 100x: 0.2 ms per step
  state->set_playing(true);
  state->start_thread();
  for (int i = 0; i < 500 && state->snapshot().step < 7; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  state->stop_thread();
  const AppSnapshot s = state->snapshot();
  CHECK(s.step == 7);
  CHECK(s.models[0].out.disp_px[0].y() == 8);
}

TEST_CASE("several parameter tables for one model in one batch replay once, with the last", "[ui]") {
  auto state = make_state(8, 4);
  const auto path = state->path();
  for (int i = 0; i < 5; ++i) state->step();
  for (double gain : {2.0, 5.0, 7.0}) {  // a slider dragged across three values between two steps
    ParamSet p = state->model(0).params();
    p.set("gain", gain);
    state->request_params(0, p);
  }
  CHECK(state->sync() == 3);
  CHECK(dynamic_cast<const HistoryModel&>(state->model(0)).set_params_calls == 1);
  CHECK(state->output(0).disp_px[0].x() == direct_output(path, 4, 7.0).x());
}

TEST_CASE("a replaced model replays the path to the current step; the other slot is untouched", "[ui]") {
  auto state = make_state(12, 4);
  const auto path = state->path();
  for (int i = 0; i < 7; ++i) state->step();  // at step 6
  const Vec2 other_before = state->output(0).disp_px[0];
  auto replacement = std::make_unique<HistoryModel>();
  ParamSet p = replacement->params();
  p.set("gain", 2.0);  // a different model: here the same kind with another gain, so its output differs
  replacement->set_params(p);
  state->request_model(1, std::move(replacement));
  CHECK(state->pending_edits() == 1);
  state->sync();
  CHECK(state->pending_edits() == 0);
  CHECK(state->current_step() == 6);
  // acc_6 = sum_{i=0..6} 2 * 0.001 (i + 1) * (i + 1), from a fresh model: 7 steps, nothing repeated.
  CHECK(state->output(1).disp_px[0].x() == direct_output(path, 6, 2.0).x());
  CHECK(state->output(1).disp_px[0].y() == 7);
  CHECK(state->output(0).disp_px[0] == other_before);
  CHECK(state->snapshot().models[1].params.get("gain") == 2.0);
  // Its checkpoints are its own: seeking back replays the replacement.
  state->request_seek(2);
  state->sync();
  CHECK(state->output(1).disp_px[0].x() == direct_output(path, 2, 2.0).x());
  CHECK_THROWS_AS(state->request_model(5, std::make_unique<HistoryModel>()), std::out_of_range);
  CHECK_THROWS_AS(state->request_model(0, nullptr), std::invalid_argument);
}

}  // namespace test_app_state
