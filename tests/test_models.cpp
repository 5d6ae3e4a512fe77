// Properties shared by every shear model: the registry, and invariance to a rigid motion of sensor and
// indenter together (only X_EI enters).
#include <catch2/catch.hpp>

#include "mini_grid.hpp"

#include "model_fixtures.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_models {

using sbtest::kMiniMarkers;

using namespace sbtest;

TEST_CASE("model registry: ids, defaults, unknown id", "[models]") {
  const auto& ids = model_ids();
  REQUIRE(ids.size() == 9);  // the five published models and HydroShear's four model-form variants
  for (const auto& id : ids) {
    const ParamSet p = default_params(id);
    CHECK(p.size() > 0);
    auto m = make_model(id, test_sensor(), sphere_indenter(4e-3));
    CHECK(m->id() == id);
    CHECK(m->params().values() == p.values());
  }
  CHECK_THROWS_AS(default_params("nope"), std::invalid_argument);
  CHECK(default_params("hydroshear").get("mu") == 0.5);
  CHECK(default_params("fots").get("lambda_d") == 0.00125);
  CHECK(default_params("fots-reimpl").get("lambda_s") == 203.3439);
  CHECK(default_params("tacsl").get("kt") == 0.1);
}

TEST_CASE("models: a non-finite pose is rejected", "[models]") {
  for (const auto& id : model_ids()) {
    auto m = make_model(id, test_sensor(), sphere_indenter(4e-3));
    Pose X = Pose::Identity();
    X.translation().x() = std::nan("");
    FieldOutput out;
    CHECK_THROWS_AS(m->step(X, 0.01, &out), std::invalid_argument);
  }
}

TEST_CASE("models: moving sensor and indenter together rigidly changes nothing", "[models]") {
  // The same X_EI trajectory composed from two different world placements of the sensor.
  const Pose X_WE1 = make_pose(Vec3(0.1, -0.2, 0.3), Quat(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized())));
  const Pose X_WE2 = make_pose(Vec3(-1.0, 0.5, 2.0), Quat(Eigen::AngleAxisd(-2.1, Vec3(0, 1, -1).normalized())));
  std::vector<Pose> traj;
  for (int k = 0; k < 12; ++k)
    traj.push_back(sphere_pose(4e-3, 0.08e-3 * k, -0.03e-3 * k, -0.1e-3 + 0.15e-3 * std::min(k, 6), Rz(0.01 * k)));
  constexpr double kRoundTol = 1e-6;  // px: double rounding through two world frames
  for (const auto& id : model_ids()) {
    auto a = make_model(id, test_sensor(), sphere_indenter(4e-3));
    auto b = a->clone();
    double seen = 0;
    for (const Pose& X : traj) {
      const Pose X_WI1 = X_WE1 * X, X_WI2 = X_WE2 * X;
      const auto da = run(*a, X_WE1.inverse() * X_WI1);
      const auto db = run(*b, X_WE2.inverse() * X_WI2);
      for (int j = 0; j < kMiniMarkers; ++j) CHECK((da[j] - db[j]).norm() < kRoundTol);
      seen = std::max(seen, max_norm(da));
    }
    CHECK(seen > 0);  // the trajectory does touch
  }
}

}  // namespace test_models
