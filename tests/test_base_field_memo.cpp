#include "core/effects/base_field_memo.hpp"

#include <array>
#include <catch2/catch.hpp>
#include <memory>

#include "core/effects/effects.hpp"
#include "model_fixtures.hpp"

// This file's names in a namespace of its own: the unity build compiles several test files as one unit.
namespace test_base_field_memo {

using namespace sb;
using sbtest::sphere_indenter;
using sbtest::test_sensor;

namespace {

constexpr double kDt = 0.01;
constexpr double kRadius = 0.004;

// The base under test with a count of the steps it takes (shared by its clones).
class CountingModel final : public ShearModel {
 public:
  CountingModel(std::unique_ptr<ShearModel> inner, std::shared_ptr<int> steps)
      : inner_(std::move(inner)), steps_(std::move(steps)) {}
  std::string id() const override { return inner_->id(); }
  const ParamSet& params() const override { return inner_->params(); }
  void set_params(const ParamSet& p) override { inner_->set_params(p); }
  void reset() override { inner_->reset(); }
  void step(const Pose& X_EI, double dt, FieldOutput* out) override {
    ++*steps_;
    inner_->step(X_EI, dt, out);
  }
  std::unique_ptr<ShearModel> clone() const override {
    return std::make_unique<CountingModel>(inner_->clone(), steps_);
  }

 private:
  std::unique_ptr<ShearModel> inner_;
  std::shared_ptr<int> steps_;
};

// HydroShear (path-dependent: the slide's stick and slip), with a pose effect and a field effect that watches
// the steps: every way the memo could go wrong shows in its field.
struct Rig {
  std::shared_ptr<int> base_steps = std::make_shared<int>(0);
  std::unique_ptr<EffectModel> model;
  Rig() {
    auto sensor = test_sensor();
    auto indenter = sphere_indenter(kRadius);
    auto base = std::make_unique<CountingModel>(make_model("hydroshear", sensor, indenter), base_steps);
    std::vector<std::unique_ptr<Effect>> fx;
    fx.push_back(make_effect("tool_frame"));
    fx.push_back(make_effect("dome_sway"));
    model = std::make_unique<EffectModel>(std::move(base), std::move(fx), sensor, indenter);
    ParamSet p = model->params();
    p.set("dome_sway.compliance_m", 2e-4);
    p.set("tool_frame.press_offset_m", 2e-4);
    model->set_params(p);
  }
  void set(const std::string& name, double value) {
    ParamSet p = model->params();
    p.set(name, value);
    model->set_params(p);
  }
};

// Above the gel, pressed 1 mm, then slid 1.5 mm along x in 0.5 mm steps: the sphere's centre at z = r - depth.
std::vector<Pose> press_and_slide(double last_y = 0) {
  std::vector<Pose> X;
  for (const auto& [x, y, depth] : std::vector<std::array<double, 3>>{{0, 0, -0.001},
                                                                      {0, 0, 0.0005},
                                                                      {0, 0, 0.001},
                                                                      {0.0005, 0, 0.001},
                                                                      {0.001, 0, 0.001},
                                                                      {0.0015, last_y, 0.001}}) {
    Pose P = Pose::Identity();
    P.translation() = Vec3(x, y, kRadius - depth);
    X.push_back(P);
  }
  return X;
}

std::vector<std::vector<Vec2>> run_path(ShearModel& m, const std::vector<Pose>& path, std::size_t first = 0) {
  std::vector<std::vector<Vec2>> fields;
  if (first == 0) m.reset();
  for (std::size_t k = first; k < path.size(); ++k) {
    FieldOutput out;
    m.step(path[k], kDt, &out);
    fields.push_back(out.disp_px);
  }
  return fields;
}

// The same model without a memo, at the same parameters: what every run must reproduce bit for bit.
std::vector<std::vector<Vec2>> fresh_run(const EffectModel& m, const std::vector<Pose>& path) {
  auto copy = m.clone();
  return run_path(*copy, path);
}

}  // namespace

TEST_CASE("BaseFieldMemo: a step replays only at the same pose and dt, and with a field when one is wanted", "[memo]") {
  BaseFieldMemo memo;
  memo.set_base_params({1.0, 2.0});
  Pose X = Pose::Identity();
  X.translation() = Vec3(0, 0, 0.003);
  FieldOutput f;
  f.disp_px = {Vec2(1, 2)};
  f.marker_in_contact = {1};
  f.p_EP = {Vec3(1, 1, 1)};
  memo.record(0, X, kDt, nullptr);  // stepped without a field
  memo.record(1, X, kDt, &f);

  FieldOutput out;
  out.p_EP = {Vec3(9, 9, 9)};
  CHECK(memo.replay(0, X, kDt, nullptr));
  CHECK_FALSE(memo.replay(0, X, kDt, &out));  // a field is wanted, none was recorded
  REQUIRE(memo.replay(1, X, kDt, &out));
  CHECK(out.disp_px == f.disp_px);
  CHECK(out.marker_in_contact == f.marker_in_contact);
  CHECK(out.p_EP.empty());  // the memo keeps no diagnostics

  Pose moved = X;
  moved.translation().x() += 1e-12;
  CHECK_FALSE(memo.replay(1, moved, kDt, nullptr));
  CHECK_FALSE(memo.replay(1, X, 2 * kDt, nullptr));
  CHECK_FALSE(memo.replay(2, X, kDt, nullptr));

  memo.record(1, moved, kDt, nullptr);  // another path from step 1: step 1 is replaced
  CHECK(memo.size() == 2);
  CHECK_FALSE(memo.replay(1, X, kDt, nullptr));
  CHECK_THROWS_AS(memo.record(3, X, kDt, nullptr), std::logic_error);

  memo.set_base_params({1.0, 2.0});  // the same parameters: kept
  CHECK(memo.size() == 2);
  memo.set_base_params({1.0, 2.5});  // others: forgotten
  CHECK(memo.size() == 0);
}

TEST_CASE(
    "EffectModel remembering its base field: a field effect's parameter changed replays the base, bit "
    "identical to a model without the memo",
    "[memo][effects]") {
  Rig rig;
  rig.model->remember_base_field(true);
  const auto path = press_and_slide();
  run_path(*rig.model, path);
  CHECK(*rig.base_steps == 6);

  rig.set("dome_sway.friction", 0.4);
  const auto replayed = run_path(*rig.model, path);
  CHECK(*rig.base_steps == 6);  // no base step: all six replayed
  const auto expected = fresh_run(*rig.model, path);
  CHECK(replayed == expected);
  CHECK(sbtest::max_norm(replayed.back()) > 0.1);  // the slide moves the pins: the comparison has a field to see
}

TEST_CASE("EffectModel remembering its base field: a pose effect's or the base's parameter changed steps the base",
          "[memo][effects]") {
  Rig rig;
  rig.model->remember_base_field(true);
  const auto path = press_and_slide();
  run_path(*rig.model, path);
  const std::string name = GENERATE(std::string("tool_frame.press_offset_m"), std::string("mu"));
  rig.set(name, name == "mu" ? 0.3 : 4e-4);
  *rig.base_steps = 0;
  const auto stepped = run_path(*rig.model, path);
  CHECK(*rig.base_steps == 6);
  CHECK(stepped == fresh_run(*rig.model, path));
}

TEST_CASE(
    "EffectModel remembering its base field: a path that departs after replayed steps brings the base up "
    "first, and a clone taken there continues as the model would",
    "[memo][effects]") {
  Rig rig;
  rig.model->remember_base_field(true);
  run_path(*rig.model, press_and_slide());
  const auto departing = press_and_slide(/*last_y=*/0.0005);  // steps 0-4 as recorded, step 5 elsewhere

  SECTION("departing at the last step") {
    *rig.base_steps = 0;
    const auto fields = run_path(*rig.model, departing);
    CHECK(*rig.base_steps == 6);  // steps 0-4 replayed by the memo, then again into the base, then step 5
    CHECK(fields == fresh_run(*rig.model, departing));
  }
  SECTION("a clone after four replayed steps") {
    rig.model->reset();
    for (std::size_t k = 0; k < 4; ++k) rig.model->step(departing[k], kDt, nullptr);
    auto clone = rig.model->clone();
    const auto continued = run_path(*clone, departing, 4);
    const auto expected = fresh_run(*rig.model, departing);
    CHECK(continued == std::vector<std::vector<Vec2>>(expected.begin() + 4, expected.end()));
  }
}

}  // namespace test_base_field_memo
