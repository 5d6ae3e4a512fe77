// TacSL penalty shear: expected values derived by hand from core/models/tacsl.hpp.
#include <catch2/catch.hpp>

#include "mini_grid.hpp"

#include "core/models/tacsl.hpp"
#include "model_fixtures.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_tacsl {

using sbtest::kMiniMarkers;

using namespace sbtest;

namespace {
constexpr double kForceTol = 1e-12;  // the "force" is metres-scale (kn = 1)
constexpr double kBox = 8e-3;        // 8 mm box: the 9 markers under it are 1.9 mm from its sides, so
                                     // for presses up to 1 mm (and 0.6 mm slides) their nearest face is
                                     // the bottom and n = -z
}  // namespace

TEST_CASE("TacSL: at rest the shear is zero", "[models][tacsl]") {
  for (const std::string id : {"tacsl", "tacsl-normalized"}) {
    auto m = make_model(id, sbtest::test_sensor(), box_indenter(kBox));
    run(*m, box_pose(kBox, 0, 0, -1e-3));
    const auto d = run(*m, box_pose(kBox, 0, 0, -1e-3));
    CHECK(max_norm(d) == 0.0);
  }
  // A sphere at rest: f_t = 0; the code's shear still carries f_n n_xy (radial); f_t only gives 0.
  auto m = make_model("tacsl", sbtest::test_sensor(), sphere_indenter(4e-3));
  ParamSet p = m->params();
  run(*m, sphere_pose(4e-3, 0, 0, 1e-3));
  const auto with_normal = run(*m, sphere_pose(4e-3, 0, 0, 1e-3));
  // Marker (1,0): d = h1, n = unit(p, 0, -(R - d)): shear x = kn h1 p / sqrt(p^2 + (R-d)^2), times 1000 px.
  const double pch = kPitchM, rr = std::sqrt(pch * pch + 9e-6), h1 = 4e-3 - rr;
  CHECK(with_normal[marker_at(1, 0)].x() == Approx(1000 * h1 * pch / rr).epsilon(1e-9));
  p.set("include_normal", 0);
  m->set_params(p);
  CHECK(max_norm(run(*m, sphere_pose(4e-3, 0, 0, 1e-3))) == 0.0);
}

TEST_CASE("TacSL: sliding gives a viscous shear capped by mu kn d; release gives zero", "[models][tacsl]") {
  auto sensor = sbtest::test_sensor();
  TacslBatch raw(false, sensor, box_indenter(kBox), 1, default_params("tacsl"));
  std::vector<Vec2> disp(kMiniMarkers);
  auto step = [&](const Pose& X, double dt) { raw.step(std::span<const Pose>(&X, 1), dt, disp, {}); };
  const double dt = 0.01;
  step(box_pose(kBox, 0, 0, -1e-3), dt);
  // 0.1 mm in 10 ms = 10 mm/s: v_rel = -v x, f_t = +min(0.1 * 0.01, 2 * 1e-3) x = 1e-3 x (static
  // branch): the documented default gain 1000 px gives 1 px.
  step(box_pose(kBox, 0.1e-3, 0, -1e-3), dt);
  CHECK(raw.last_shear(0)[marker_at(0, 0)].x() == Approx(1e-3).margin(kForceTol));
  CHECK(disp[marker_at(0, 0)].x() == Approx(1.0).epsilon(1e-9));
  CHECK(std::abs(disp[marker_at(0, 0)].y()) < 1e-9);
  // 0.5 mm in 10 ms = 50 mm/s: kt v = 5e-3 > mu kn d = 2e-3: capped.
  step(box_pose(kBox, 0.6e-3, 0, -1e-3), dt);
  CHECK(raw.last_shear(0)[marker_at(0, 0)].x() == Approx(2e-3).margin(kForceTol));
  // Markers outside the box have no contact, hence no shear.
  CHECK(disp[marker_at(3, 0)].norm() == 0.0);
  step(box_pose(kBox, 0.6e-3, 0, 0.5e-3), dt);
  CHECK(max_norm(disp) == 0.0);

  // Normalised: unit vectors times gain_px (1) where |s| > 1e-4.
  auto norm = make_model("tacsl-normalized", sensor, box_indenter(kBox));
  run(*norm, box_pose(kBox, 0, 0, -1e-3));
  const auto d = run(*norm, box_pose(kBox, 0, -0.1e-3, -1e-3));
  CHECK((d[marker_at(0, 0)] - Vec2(0, -1)).norm() < 1e-12);
  // Below the threshold (0.1 mm/s: |f_t| = 1e-5 < 1e-4): zero.
  const auto slow = run(*norm, box_pose(kBox, 0, -0.101e-3, -1e-3));
  CHECK(max_norm(slow) == 0.0);
}

}  // namespace test_tacsl
