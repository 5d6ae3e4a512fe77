// The public API (include/shearbench/sensor_model.hpp): every function, against hand-derived values or the
// core it wraps (ShearModel::step on the same path, bit for bit).
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <numbers>
#include <shearbench/sensor_model.hpp>
#include <string>
#include <thread>
#include <vector>

#include "core/api/bench_run.hpp"
#include "core/api/sensor_model_impl.hpp"
#include "core/calibration/param_sets.hpp"
#include "core/data/scene.hpp"
#include "core/effects/model_spec.hpp"
#include "core/models/bench_workload.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one.
namespace test_api_sensor_model {

namespace {

using shearbench::Config;
using shearbench::SensorModel;

constexpr double kSphereR = 0.004;
const char* kSphere = R"({"shape": "sphere", "radius_m": 0.004})";

// A press of the 4 mm sphere to `depth` at (x, y) in E, no rotation: the sphere's centre is at z = R - depth.
std::vector<double> press(double x, double y, double depth) { return {x, y, kSphereR - depth, 1, 0, 0, 0}; }

// A path of `n` poses: a 1 mm press over the first third, then a 1.5 mm slide along x_E and a 10 degree
// twist about z_E.
std::vector<std::vector<double>> press_slide_twist(int n) {
  std::vector<std::vector<double>> path;
  for (int k = 0; k < n; ++k) {
    const double s = std::clamp(3.0 * k / n, 0.0, 1.0), u = std::clamp(3.0 * k / n - 1, 0.0, 1.0);
    const double half = 0.5 * u * 10 * std::numbers::pi / 180;
    path.push_back({1.5e-3 * u, 0, kSphereR - 1e-3 * s, std::cos(half), 0, 0, std::sin(half)});
  }
  return path;
}

Config sphere_config(const std::string& model, int envs = 1) {
  Config c;
  c.model = model;
  c.indenter = kSphere;
  c.envs = envs;
  return c;
}

// The reference: the core's ShearModel for `model` at the default set's parameters, stepped with make_pose.
std::unique_ptr<sb::ShearModel> reference(const std::string& model) {
  auto sensor = std::make_shared<const sb::Sensor>(sb::make_default_sensor());
  sb::IndenterSpec spec;
  spec.shape = "sphere";
  spec.radius_m = kSphereR;
  auto indenter = std::make_shared<const sb::Indenter>(sb::build_indenter(spec, "", ""));
  auto m = sb::make_spec_model(model, sensor, indenter);
  m->set_params(sb::load_param_set(sb::kDefaultParamSet).params(model));
  return m;
}

sb::Pose pose_of(const std::vector<double>& v) {
  return sb::make_pose(sb::Vec3(v[0], v[1], v[2]), v[3], v[4], v[5], v[6]);
}

}  // namespace

TEST_CASE("api: a pose out of contact gives a zero field for every model form", "[api]") {
  for (const std::string& model : shearbench::model_names()) {
    SensorModel m = SensorModel::create(sphere_config(model));
    REQUIRE(m.markers() == 63);  // the GelSight Mini's 9 x 7 grid
    std::vector<double> field(63 * 2, 99.0);
    // The sphere's lowest point 6 mm above the gel: nothing touches.
    m.step(press(0, 0, -6e-3), 0.02, field);
    for (double v : field) CHECK(v == 0.0);
  }
}

TEST_CASE("api: the field equals ShearModel::step's on the same path, bit for bit", "[api]") {
  // Every form, and the residual loop's answer on twin_sphere35 (a form with an effect: one model per env).
  std::vector<std::string> models = shearbench::model_names();
  models.push_back("hydroshear-contact+tool_frame");
  const auto path = press_slide_twist(24);
  for (const std::string& model : models) {
    INFO(model);
    SensorModel api = SensorModel::create(sphere_config(model));
    auto ref = reference(model);
    std::vector<double> field(63 * 2);
    sb::FieldOutput out;
    double peak = 0;
    for (const auto& X : path) {
      api.step(X, 0.02, field);
      ref->step(pose_of(X), 0.02, &out);
      REQUIRE(out.disp_px.size() == 63);
      for (int j = 0; j < 63; ++j) {
        REQUIRE(field[2 * j] == out.disp_px[j].x());
        REQUIRE(field[2 * j + 1] == out.disp_px[j].y());
        peak = std::max(peak, out.disp_px[j].norm());
      }
    }
    CHECK(peak > 0.1);  // the path is in contact: the comparison is not of zeros
  }
}

TEST_CASE("api: envs are independent; reset(env) restarts one env only", "[api]") {
  const auto path = press_slide_twist(12);
  SensorModel one = SensorModel::create(sphere_config("hydroshear"));
  SensorModel two = SensorModel::create(sphere_config("hydroshear", 2));
  REQUIRE(two.envs() == 2);
  std::vector<double> f1(126), f2(252), X2(14);
  for (const auto& X : path) {
    // env 0 follows the path, env 1 stays out of contact.
    std::copy(X.begin(), X.end(), X2.begin());
    const auto away = press(0, 0, -6e-3);
    std::copy(away.begin(), away.end(), X2.begin() + 7);
    one.step(X, 0.02, f1);
    two.step(X2, 0.02, f2);
    for (int i = 0; i < 126; ++i) REQUIRE(f2[i] == f1[i]);
    for (int i = 126; i < 252; ++i) REQUIRE(f2[i] == 0.0);
  }
  // After reset(0) env 0 is at rest: the last pose then is a fresh press (no slide history), unlike env 0 of
  // a model that came along the path. The fresh model on the same pose is what reset(0) must give.
  two.reset(0);
  SensorModel fresh = SensorModel::create(sphere_config("hydroshear", 2));
  std::vector<double> ff(252);
  two.step(X2, 0.02, f2);
  fresh.step(X2, 0.02, ff);
  for (int i = 0; i < 252; ++i) REQUIRE(f2[i] == ff[i]);
  // reset() of all: the same.
  two.reset();
  fresh.reset();
  two.step(X2, 0.02, f2);
  fresh.step(X2, 0.02, ff);
  for (int i = 0; i < 252; ++i) REQUIRE(f2[i] == ff[i]);
}

TEST_CASE("api: two instances stepped on two threads at once give what each gives alone", "[api]") {
  // The threading contract: instances share nothing mutable. Each thread builds and steps its own model (the
  // construction reads the parameter set's file too); the fields must equal a sequential run's bit for bit.
  const auto path = press_slide_twist(12);
  const auto run = [&](const std::string& model) {
    SensorModel m = SensorModel::create(sphere_config(model, 4));
    std::vector<double> X(4 * 7), field(4 * 63 * 2), all;
    for (const auto& pose : path) {
      for (int e = 0; e < 4; ++e) std::copy(pose.begin(), pose.end(), X.begin() + 7 * e);
      m.step(X, 0.02, field);
      all.insert(all.end(), field.begin(), field.end());
    }
    return all;
  };
  const std::vector<double> a_alone = run("hydroshear"), b_alone = run("hydroshear-contact+tool_frame");
  std::vector<double> a, b;
  std::thread ta([&] { a = run("hydroshear"); });
  std::thread tb([&] { b = run("hydroshear-contact+tool_frame"); });
  ta.join();
  tb.join();
  CHECK(a == a_alone);
  CHECK(b == b_alone);
}

TEST_CASE("api: step_world is step at X_EI = X_WE^-1 X_WI", "[api]") {
  // X_WE: the gel 10 cm up, turned 90 degrees about world x; X_WI = X_WE X_EI with X_EI a 1 mm press at
  // (0.5 mm, 0, .): q = (cos 45, sin 45, 0, 0). By hand, X_WI's translation is X_WE's plus R_x(90) applied
  // to p_EI = (0.5e-3, 0, 3e-3): (0.5e-3, -3e-3, 0) -> (0.5e-3, -3e-3, 0.1); its rotation is X_WE's.
  const double c = std::sqrt(0.5);
  const std::vector<double> X_WE = {0, 0, 0.1, c, c, 0, 0};
  const std::vector<double> X_WI = {0.5e-3, -3e-3, 0.1, c, c, 0, 0};
  SensorModel a = SensorModel::create(sphere_config("tacsl"));
  SensorModel b = SensorModel::create(sphere_config("tacsl"));
  std::vector<double> fa(126), fb(126);
  a.step_world(X_WE, X_WI, 0.02, fa);
  b.step(press(0.5e-3, 0, 1e-3), 0.02, fb);
  double peak = 0;
  for (int i = 0; i < 126; ++i) {
    CHECK(fa[i] == Approx(fb[i]).margin(1e-9));  // the composed pose differs in the last bits only
    peak = std::max(peak, std::abs(fb[i]));
  }
  CHECK(peak > 0.1);
}

TEST_CASE("api: the contact flags mark the markers under the indenter", "[api]") {
  // A 1 mm press of the 4 mm sphere at the centre: contact radius sqrt(2 R d - d^2) = sqrt(7) mm = 2.65 mm.
  // The centre marker (0 mm) lies inside; the corner marker (4 x 2.09, 3 x 2.09 mm: 10.5 mm away) outside.
  SensorModel m = SensorModel::create(sphere_config("hydroshear"));
  std::vector<double> field(126);
  std::vector<std::uint8_t> contact(63, 7);
  m.step(press(0, 0, 1e-3), 0.02, field, contact);
  CHECK(contact[3 * 9 + 4] == 1);
  CHECK(contact[0] == 0);
}

TEST_CASE("api: the sensor's markers and scale", "[api]") {
  SensorModel m = SensorModel::create(sphere_config("fots"));
  const std::vector<double> rest = m.markers_rest_px();
  REQUIRE(rest.size() == 126);
  // The first marker of the 9 x 7 grid at 33 px pitch around (159.5, 119.5): (159.5 - 4 * 33, 119.5 - 3 * 33).
  CHECK(rest[0] == Approx(27.5));
  CHECK(rest[1] == Approx(20.5));
  CHECK(m.mm_per_px() == Approx(0.0634));
  CHECK(m.model() == "fots");
  CHECK(m.params_json().find("\"") != std::string::npos);
}

TEST_CASE("api: bad input throws shearbench::Error naming what and where; the state is unchanged", "[api]") {
  Config bad = sphere_config("nope");
  CHECK_THROWS_WITH(SensorModel::create(bad), Catch::Contains("model: unknown model") && Catch::Contains("nope"));
  CHECK_THROWS_AS(SensorModel::create(sphere_config("hydroshear", 0)), shearbench::Error);
  Config bad_json = sphere_config("hydroshear");
  bad_json.indenter = "{not json";
  CHECK_THROWS_WITH(SensorModel::create(bad_json), Catch::StartsWith("indenter: not JSON"));
  Config bad_set = sphere_config("hydroshear");
  bad_set.param_set = "no_such_set";
  CHECK_THROWS_AS(SensorModel::create(bad_set), shearbench::Error);

  SensorModel m = SensorModel::create(sphere_config("hydroshear", 2));
  std::vector<double> field(252), X(14, 0.0);
  X[3] = X[10] = 1;
  CHECK_THROWS_WITH(m.step(std::span<const double>(X).first(7), 0.02, field),
                    Catch::Contains("X_EI: 7 values, expected 14"));
  CHECK_THROWS_WITH(m.step(X, 0.02, std::span<double>(field).first(10)), Catch::Contains("disp_px: 10 values"));
  CHECK_THROWS_WITH(m.step(X, 0.0, field), Catch::StartsWith("dt: must be finite and > 0"));
  std::vector<double> nan = X;
  nan[7] = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH(m.step(nan, 0.02, field), "X_EI[env 1]: a pose value is not finite");
  std::vector<double> zero_q = X;
  zero_q[3] = 0;
  CHECK_THROWS_WITH(m.step(zero_q, 0.02, field), "X_EI[env 0]: quaternion has zero norm");
  CHECK_THROWS_WITH(m.reset(2), Catch::Contains("env 2 outside 0..1"));
  // None of that moved a state: a press now is a fresh model's press.
  SensorModel fresh = SensorModel::create(sphere_config("hydroshear", 2));
  const auto p = press(0, 0, 1e-3);
  std::copy(p.begin(), p.end(), X.begin());
  std::vector<double> ff(252);
  m.step(X, 0.02, field);
  fresh.step(X, 0.02, ff);
  for (int i = 0; i < 252; ++i) REQUIRE(field[i] == ff[i]);
}

TEST_CASE("api: names, parameter sets, the loop's answer", "[api]") {
  CHECK(shearbench::model_names() == sb::model_ids());
  const auto effects = shearbench::effect_names();
  CHECK(std::find(effects.begin(), effects.end(), "tool_frame") != effects.end());
  const auto sets = shearbench::param_set_names();
  CHECK(std::find(sets.begin(), sets.end(), "twin_sphere35") != sets.end());
  CHECK(shearbench::version() == SHEARBENCH_VERSION);

  // docs/residuals/twin_sphere35_hydroshear: the answer is the contact form with tool_frame.
  Config c = shearbench::loop_answer("twin_sphere35_hydroshear");
  CHECK(c.model == "hydroshear-contact+tool_frame");
  CHECK(c.params_file.ends_with("docs/residuals/twin_sphere35_hydroshear/report_params.json"));
  c.indenter = kSphere;
  SensorModel m = SensorModel::create(c);
  // The fitted mu of that report (2.1895...) replaces the set's.
  CHECK(m.params_json().find("\"mu\":2.18953991") != std::string::npos);
  CHECK_THROWS_WITH(shearbench::loop_answer("no_such_run"), Catch::Contains("no residual run 'no_such_run'"));
}

TEST_CASE("api: a sensor block as a scene's", "[api]") {
  Config c = sphere_config("tacsl");
  c.sensor = R"({"gel": "flat", "markers": "11x9"})";  // 11 x 9 markers
  CHECK(SensorModel::create(c).markers() == 99);
  c.sensor = R"({"gel": "flat", "nope": 1})";
  CHECK_THROWS_WITH(SensorModel::create(c), Catch::Contains("sensor") && Catch::Contains("nope"));
}

TEST_CASE("api: a scene gives the sensor, the indenter and its params table", "[api]") {
  Config c;
  c.model = "hydroshear";
  c.scene = std::string(SHEARBENCH_SOURCE_DIR) + "/scenes/shear_sphere.json";
  SensorModel m = SensorModel::create(c);
  CHECK(m.markers() == 63);
  c.indenter = kSphere;
  CHECK_THROWS_WITH(SensorModel::create(c), Catch::StartsWith("scene: a scene gives the sensor"));
}

TEST_CASE("api: the bench workload's poses and field are the API's", "[api]") {
  const int envs = 3, steps = 12;  // the press completes at k = 10
  const std::vector<double> v = shearbench::bench_poses(envs, steps);
  REQUIRE(v.size() == static_cast<std::size_t>(steps * envs * 2 * 7));
  sb::BenchWorkloadSpec spec;
  spec.envs = envs;
  spec.steps = steps;
  const auto traj = sb::bench_trajectory(spec);
  // Step 5, env 2, right pad: the same pose, as 7 numbers.
  const sb::Pose& X = traj[5][2 * 2 + 1];
  const double* p = v.data() + ((5 * envs + 2) * 2 + 1) * 7;
  CHECK(pose_of({p, p + 7}).isApprox(X, 1e-15));
  CHECK(shearbench::bench_dt() == sb::kBenchDt);

  // BenchWorkload's last field is a SensorModel's stepped on bench_poses with the published values.
  sb::BenchWorkload w("hydroshear", envs, steps);
  w.run();
  Config c;
  c.model = "hydroshear";
  c.param_set = "published";
  c.indenter = "bench_peg";
  c.envs = 2 * envs;
  SensorModel m = SensorModel::create(c);
  std::vector<double> field(2 * envs * 63 * 2);
  for (int k = 0; k < steps; ++k)
    m.step(std::span<const double>(v).subspan(k * 2 * envs * 7, 2 * envs * 7), shearbench::bench_dt(), field);
  REQUIRE(w.last_field().size() == field.size());
  double peak = 0;
  for (std::size_t i = 0; i < field.size(); ++i) {
    REQUIRE(w.last_field()[i] == field[i]);
    peak = std::max(peak, std::abs(field[i]));
  }
  CHECK(peak > 0.1);
  CHECK_THROWS_AS(shearbench::bench_poses(1, 51), shearbench::Error);
}

}  // namespace test_api_sensor_model
