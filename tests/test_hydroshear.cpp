// HydroShear: expected values derived by hand from the update rules in core/models/hydroshear.hpp.
#include <catch2/catch.hpp>

#include "mini_grid.hpp"

#include "core/models/hydroshear.hpp"
#include "model_fixtures.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_hydroshear {

using sbtest::kMiniMarkers;

using namespace sbtest;

namespace {

constexpr double kTol = 1e-12;   // metres: exact state arithmetic (a few roundings of 1e-3 values)
constexpr double kPxTol = 1e-9;  // px: fields computed two ways
constexpr double kBox = 6e-3;    // box indenter side

ParamSet hs_params() { return default_params("hydroshear"); }

// The centre-marker shear of a set of stuck points: kappa_s * sum_i w (-f_x) exp(-lambda_s |m - a_i|^2).
double centre_shear_x(const std::vector<Vec3>& anchors, double w_times_minus_f, double kappa_s, double lambda_s) {
  double s = 0;
  for (const Vec3& a : anchors) s += std::exp(-lambda_s * a.squaredNorm());  // centre marker at the origin
  return kappa_s * w_times_minus_f * s;
}

}  // namespace

TEST_CASE("HydroShear: no contact gives a zero field and no tracked points", "[models][hydroshear]") {
  auto model = make_model("hydroshear", test_sensor(), sphere_indenter(4e-3));
  FieldOutput out;
  model->step(sphere_pose(4e-3, 0, 0, -1e-3), 0.01, &out);  // 1 mm above the gel
  REQUIRE(out.disp_px.size() == kMiniMarkers);
  CHECK(max_norm(out.disp_px) == 0.0);
  CHECK(out.p_EP.empty());
  for (auto c : out.marker_in_contact) CHECK(c == 0);
}

TEST_CASE("HydroShear: a centred sphere press is an outward, symmetric dilation", "[models][hydroshear]") {
  const double R = 4e-3, d = 1e-3;
  auto model = make_model("hydroshear", test_sensor(), sphere_indenter(R));
  run(*model, sphere_pose(R, 0, 0, -0.1e-3));
  const auto disp = run(*model, sphere_pose(R, 0, 0, d));
  // Pure vertical stick: delta_t = 0, so the state has no tangential part and the shear term is 0;
  // the field is the dilation. Contact radius sqrt(2 R d - d^2) = 2.65 mm: markers (0,0), (+-1,0), (0,+-1)
  // (pitch 2.09 mm; the diagonal at 2.96 mm is outside) with h0 = d and h1 = R - sqrt(p^2 + (R-d)^2).
  const double p = kPitchM, h0 = d, h1 = R - std::sqrt(p * p + (R - d) * (R - d));
  const double kd = default_params("hydroshear").get("kappa_d"), ld = 20000;
  auto W = [&](double r2) { return std::exp(-ld * r2); };
  // Marker (1, 0): h0 W(p^2) (p,0) + h1 [W(4p^2) (2p,0) + 2 W(2p^2) (p,0)] (the (1,0) self term is 0).
  const double expected_x = kd * (h0 * W(p * p) * p + h1 * (W(4 * p * p) * 2 * p + 2 * W(2 * p * p) * p));
  CHECK(disp[marker_at(1, 0)].x() == Approx(expected_x).epsilon(1e-12));
  CHECK(std::abs(disp[marker_at(1, 0)].y()) < kPxTol);
  CHECK(disp[marker_at(0, 0)].norm() < kPxTol);
  for (int dr = -3; dr <= 3; ++dr)
    for (int dc = -4; dc <= 4; ++dc) {
      const Vec2 v = disp[marker_at(dc, dr)];
      const Vec2 radial(dc, dr);
      // Mirror symmetry in x and y, and swap symmetry inside the central 7 x 7 block.
      CHECK((disp[marker_at(-dc, dr)] - Vec2(-v.x(), v.y())).norm() < kPxTol);
      CHECK((disp[marker_at(dc, -dr)] - Vec2(v.x(), -v.y())).norm() < kPxTol);
      if (std::abs(dc) <= 3) CHECK((disp[marker_at(dr, dc)] - Vec2(v.y(), v.x())).norm() < kPxTol);
      if (dc == 0 && dr == 0) continue;
      CHECK(v.dot(radial) > 0);  // outward
      // On the axes and diagonals the field is exactly radial (a mirror line through the marker).
      if (dc == 0 || dr == 0 || std::abs(dc) == std::abs(dr))
        CHECK(std::abs(v.x() * radial.y() - v.y() * radial.x()) < kPxTol);
    }
}

TEST_CASE("HydroShear: stick grows linearly, slip plateaus at mu * depth", "[models][hydroshear]") {
  auto sensor = test_sensor();
  auto box = box_indenter(kBox);
  ParamSet params = hs_params();
  params.set("lambda_d", 1e7);  // the dilation kernel becomes exp(-43.8) between markers: shear alone
  HydroShearBatch batch(sensor, box, 1, params);
  std::vector<Vec2> disp(kMiniMarkers);
  auto step = [&](const Pose& X) { batch.step(std::span<const Pose>(&X, 1), 0.01, disp, {}); };
  const double h = 0.5e-3, mu = 0.5;
  // Enter from 0.05 mm above: alpha makes the normal state the depth exactly, u_n = h.
  step(box_pose(kBox, 0, 0, 0.05e-3));
  CHECK(batch.tracked(0).empty());
  step(box_pose(kBox, 0, 0, -0.1e-3));
  // Crossing step: alpha = 0.1 / 0.15, delta_z = alpha * 0.15 mm = 0.1 mm.
  for (const auto& q : batch.tracked(0)) CHECK(q.u_E.z() == Approx(0.1e-3).margin(kTol));
  step(box_pose(kBox, 0, 0, -h));
  REQUIRE(batch.tracked(0).size() == 25);
  for (const auto& q : batch.tracked(0)) {
    CHECK(q.u_n == Approx(h).margin(kTol));
    CHECK(q.u_E.head<2>().norm() < kTol);
  }
  CHECK(max_norm(disp) < kPxTol);  // no tangential state yet

  // Slide +x in 0.05 mm steps. Stick while s <= mu h = 0.25 mm: u_t = -s, anchors stay put, so the
  // centre-marker shear is kappa_s * h * s * sum_i exp(-lambda_s |a_i|^2), linear in s.
  const double ks = params.get("kappa_s"), ls = params.get("lambda_s");
  std::vector<Vec3> anchors;
  for (const Vec3& p : box->samples.p_IS) anchors.emplace_back(p.x(), p.y(), 0);
  std::vector<double> centre;
  for (int k = 1; k <= 4; ++k) {
    const double s = 0.05e-3 * k;
    step(box_pose(kBox, s, 0, -h));
    for (const auto& q : batch.tracked(0)) {
      CHECK(q.u_E.x() == Approx(-s).margin(kTol));
      CHECK(q.state == PointState::kStick);
    }
    CHECK(disp[marker_at(0, 0)].x() == Approx(centre_shear_x(anchors, h * s, ks, ls)).epsilon(1e-10));
    centre.push_back(disp[marker_at(0, 0)].x());
  }
  CHECK(centre[3] == Approx(4 * centre[0]).epsilon(1e-10));
  // Beyond: |u_t| = mu h, the anchors trail the points by mu h.
  for (double s : {0.3e-3, 0.4e-3, 0.6e-3}) {
    step(box_pose(kBox, s, 0, -h));
    for (const auto& q : batch.tracked(0)) {
      CHECK(q.u_E.x() == Approx(-mu * h).margin(kTol));
      CHECK(q.state == PointState::kSlip);
    }
    std::vector<Vec3> slid;
    for (const Vec3& a : anchors) slid.push_back(a + Vec3(s - mu * h, 0, 0));
    CHECK(disp[marker_at(0, 0)].x() == Approx(centre_shear_x(slid, h * mu * h, ks, ls)).epsilon(1e-10));
    CHECK(disp[marker_at(0, 0)].x() > 0);  // markers move with the indenter
  }
}

TEST_CASE("HydroShear: crossing fraction alpha and the reset on leaving", "[models][hydroshear]") {
  // One tracked point at the bottom of a tiny box; it moves diagonally from phi = +0.1 mm to -0.3 mm:
  // alpha = 0.3 / 0.4 = 0.75, delta = 0.75 * (-0.4, 0, +0.4) mm = (-0.3, 0, +0.3) mm.
  auto sensor = test_sensor();
  auto ind = box_indenter(2e-3, 1);
  for (double mu : {2.0, 0.5}) {
    ParamSet params = hs_params();
    params.set("mu", mu);
    HydroShearBatch batch(sensor, ind, 1, params);
    std::vector<Vec2> disp(kMiniMarkers);
    auto step = [&](const Pose& X) { batch.step(std::span<const Pose>(&X, 1), 0.01, disp, {}); };
    step(box_pose(2e-3, 0, 0, 0.1e-3));
    step(box_pose(2e-3, 0.4e-3, 0, -0.3e-3));
    REQUIRE(batch.tracked(0).size() == 1);
    const HydroShearPoint q = batch.tracked(0)[0];  // a copy: tracked() returns by value
    CHECK(q.u_n == Approx(0.3e-3).margin(kTol));
    // mu = 2: |u_t| = 0.3 <= 0.6 mm, stick; mu = 0.5: clipped to 0.15 mm, slip.
    CHECK(q.u_E.x() == Approx(mu == 2.0 ? -0.3e-3 : -0.15e-3).margin(kTol));
    CHECK(q.state == (mu == 2.0 ? PointState::kStick : PointState::kSlip));
    // In -> in (alpha = 1): a further 0.1 mm down adds exactly 0.1 mm.
    step(box_pose(2e-3, 0.4e-3, 0, -0.4e-3));
    CHECK(batch.tracked(0)[0].u_n == Approx(0.4e-3).margin(kTol));
    // Leaving resets the state.
    step(box_pose(2e-3, 0.4e-3, 0, 0.2e-3));
    CHECK(batch.tracked(0).empty());
    CHECK(max_norm(disp) == 0.0);
  }
}

TEST_CASE("HydroShear: the first step after a reset loses penetration already present", "[models][hydroshear]") {
  auto box = box_indenter(kBox);
  HydroShearBatch batch(test_sensor(), box, 1, hs_params());
  std::vector<Vec2> disp(kMiniMarkers);
  const Pose X0 = box_pose(kBox, 0, 0, -0.3e-3), X1 = box_pose(kBox, 0, 0, -0.5e-3);
  batch.step(std::span<const Pose>(&X0, 1), 0.01, disp, {});
  for (const auto& q : batch.tracked(0)) CHECK(q.u_n == 0.0);  // prev = current (authors)
  batch.step(std::span<const Pose>(&X1, 1), 0.01, disp, {});
  for (const auto& q : batch.tracked(0)) CHECK(q.u_n == Approx(0.2e-3).margin(kTol));
}

TEST_CASE("HydroShear: the same final pose by two paths gives different fields", "[models][hydroshear]") {
  auto sensor = test_sensor();
  auto box = box_indenter(kBox);
  auto a = make_model("hydroshear", sensor, box), b = make_model("hydroshear", sensor, box);
  run(*a, box_pose(kBox, 0, 0, 0.1e-3));
  run(*a, box_pose(kBox, 0, 0, -0.5e-3));
  const auto slid = run(*a, box_pose(kBox, 0.4e-3, 0, -0.5e-3));
  run(*b, box_pose(kBox, 0.4e-3, 0, 0.1e-3));
  const auto pressed = run(*b, box_pose(kBox, 0.4e-3, 0, -0.5e-3));
  // Same pose, so the same dilation; the slid path carries a tangential state of -mu h.
  CHECK((slid[marker_at(0, 0)] - pressed[marker_at(0, 0)]).x() > 1e-3);
}

TEST_CASE("HydroShear: a counter-clockwise twist moves markers counter-clockwise", "[models][hydroshear]") {
  auto model = make_model("hydroshear", test_sensor(), box_indenter(kBox, 7, 0.8e-3));
  run(*model, box_pose(kBox, 0, 0, 0.1e-3));
  const auto before = run(*model, box_pose(kBox, 0, 0, -0.5e-3));
  const auto after = run(*model, box_pose(kBox, 0, 0, -0.5e-3, 0.05));  // +0.05 rad about +z
  // Stuck point at r moves by ~theta z x r; u_t = -that; markers follow the motion: +x marker goes +y.
  const Vec2 dx = after[marker_at(1, 0)] - before[marker_at(1, 0)];
  const Vec2 dy = after[marker_at(0, 1)] - before[marker_at(0, 1)];
  CHECK(dx.y() > 0);
  CHECK(dy.x() < 0);
  CHECK(std::abs(dx.x()) < 0.05 * dx.y());
}

TEST_CASE("HydroShear: rolling a sphere about its centre creates shear; release returns to zero",
          "[models][hydroshear]") {
  const double R = 4e-3, d = 0.8e-3;
  auto model = make_model("hydroshear", test_sensor(), sphere_indenter(R));
  run(*model, sphere_pose(R, 0, 0, -0.1e-3));
  const auto pressed = run(*model, sphere_pose(R, 0, 0, d));
  FieldOutput out;
  model->step(sphere_pose(R, 0, 0, d, Rx(0.05)), 0.01, &out);
  // Rotating +x about the centre moves the bottom (z = -R) points toward +y: markers go +y.
  const Vec2 change = out.disp_px[marker_at(0, 0)] - pressed[marker_at(0, 0)];
  CHECK(change.y() > 1e-3);
  CHECK(!out.p_EP.empty());
  CHECK(out.p_EP.size() == out.anchor_EP.size());
  model->step(sphere_pose(R, 0, 0, -0.5e-3, Rx(0.05)), 0.01, &out);
  CHECK(max_norm(out.disp_px) == 0.0);
  CHECK(out.p_EP.empty());
}

TEST_CASE("HydroShear: gravity augmentation shifts the output only", "[models][hydroshear]") {
  auto box = box_indenter(kBox);
  ParamSet params = hs_params();
  params.set("lambda_d", 1e7);
  params.set("g_aug", 0.1e-3);  // along the default direction -x_E
  HydroShearBatch batch(test_sensor(), box, 1, params);
  std::vector<Vec2> disp(kMiniMarkers);
  const Pose X0 = box_pose(kBox, 0, 0, 0.1e-3), X1 = box_pose(kBox, 0, 0, -0.5e-3);
  batch.step(std::span<const Pose>(&X0, 1), 0.01, disp, {});
  batch.step(std::span<const Pose>(&X1, 1), 0.01, disp, {});
  const Vec2 first = disp[marker_at(0, 0)];
  batch.step(std::span<const Pose>(&X1, 1), 0.01, disp, {});
  for (const auto& q : batch.tracked(0)) CHECK(q.u_E.head<2>().norm() < kTol);  // nothing committed
  // Virtual step -0.1 mm in x (stick, 0.1 < mu h): G_t = +0.1 mm; anchors at p + G; markers move -x.
  std::vector<Vec3> anchors;
  for (const Vec3& p : box->samples.p_IS) anchors.emplace_back(p.x() + 0.1e-3, p.y(), 0);
  const double expected = -centre_shear_x(anchors, 0.5e-3 * 0.1e-3, params.get("kappa_s"), params.get("lambda_s"));
  CHECK(disp[marker_at(0, 0)].x() == Approx(expected).epsilon(1e-10));
  CHECK((disp[marker_at(0, 0)] - first).norm() < kPxTol);  // not accumulated
}

TEST_CASE("HydroShear: weight and normal options", "[models][hydroshear]") {
  auto box = box_indenter(kBox);
  ParamSet paper = hs_params();
  paper.set("weight", 1);
  paper.set("lambda_d", 1e7);
  ParamSet code = paper;
  code.set("weight", 0);
  HydroShearBatch a(test_sensor(), box, 1, code), b(test_sensor(), box, 1, paper);
  std::vector<Vec2> da(kMiniMarkers), db(kMiniMarkers);
  // Enter already pressed (first-step loss): code weight u_n = 0.2 mm, paper weight depth = 0.5 mm.
  for (const Pose& X :
       {box_pose(kBox, 0, 0, -0.3e-3), box_pose(kBox, 0, 0, -0.5e-3), box_pose(kBox, 0.1e-3, 0, -0.5e-3)}) {
    a.step(std::span<const Pose>(&X, 1), 0.01, da, {});
    b.step(std::span<const Pose>(&X, 1), 0.01, db, {});
  }
  CHECK(db[marker_at(0, 0)].x() == Approx(da[marker_at(0, 0)].x() * 0.5 / 0.2).epsilon(1e-10));
  // For a flat bottom the indenter normal is -z, so the paper's normal gives the code's field.
  ParamSet ind = code;
  ind.set("normal", 1);
  HydroShearBatch c(test_sensor(), box, 1, ind);
  std::vector<Vec2> dc(kMiniMarkers);
  for (const Pose& X :
       {box_pose(kBox, 0, 0, -0.3e-3), box_pose(kBox, 0, 0, -0.5e-3), box_pose(kBox, 0.1e-3, 0, -0.5e-3)})
    c.step(std::span<const Pose>(&X, 1), 0.01, dc, {});
  for (int j = 0; j < kMiniMarkers; ++j) CHECK((dc[j] - da[j]).norm() < kPxTol);
}

TEST_CASE("HydroShear: a batch of slots equals independent single models", "[models][hydroshear]") {
  auto sensor = test_sensor();
  auto sphere = sphere_indenter(4e-3);
  const int n = 9;
  HydroShearBatch batch(sensor, sphere, n, hs_params());
  std::vector<std::unique_ptr<ShearModel>> singles;
  for (int i = 0; i < n; ++i) singles.push_back(make_model("hydroshear", sensor, sphere));
  std::vector<Vec2> disp(n * kMiniMarkers);
  for (int k = 0; k < 6; ++k) {
    std::vector<Pose> X;
    for (int i = 0; i < n; ++i) X.push_back(sphere_pose(4e-3, 0.1e-3 * i * k, -0.05e-3 * k, 0.2e-3 * k - 0.1e-3));
    batch.step(X, 0.01, disp, {});
    for (int i = 0; i < n; ++i) {
      const auto single = run(*singles[i], X[i]);
      for (int j = 0; j < kMiniMarkers; ++j) CHECK((single[j] - disp[i * kMiniMarkers + j]).norm() == 0.0);
    }
  }
}

}  // namespace test_hydroshear
