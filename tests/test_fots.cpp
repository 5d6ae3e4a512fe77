// FOTS (original, lifted to poses) and FOTS (Reimpl.): expected values derived by hand from the
// formulas in core/models/fots.hpp.
#include <catch2/catch.hpp>

#include "mini_grid.hpp"

#include "core/models/fots.hpp"
#include "model_fixtures.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_fots {

using sbtest::kMiniMarkers;

using namespace sbtest;

namespace {
constexpr double kPxTol = 1e-9;  // px: identical formulas evaluated twice
constexpr double kBox = 6e-3;
const double kPxPerM = Camera{}.px_per_metre();

std::unique_ptr<ShearModel> fots_without_dilation(const std::string& id, std::shared_ptr<const Indenter> ind) {
  auto m = make_model(id, test_sensor(), std::move(ind));
  ParamSet p = m->params();
  // Kernel exp(-lambda_d * pitch^2) = exp(-1089) (original, px^-2) or exp(-209) (reimpl, m^-1): the
  // marker-to-marker dilation vanishes and the self term is zero.
  p.set("lambda_d", id == "fots" ? 1.0 : 1e5);
  m->set_params(p);
  return m;
}
}  // namespace

TEST_CASE("twist_about_z is the in-plane angle and ignores in-plane-axis rolls", "[models][fots]") {
  CHECK(twist_about_z(Rz(0.3)) == Approx(0.3).epsilon(1e-14));
  CHECK(twist_about_z(Rz(-2.0)) == Approx(-2.0).epsilon(1e-14));
  CHECK(std::abs(twist_about_z(Rx(0.4))) < 1e-15);
  CHECK(std::abs(twist_about_z(Ry(-0.7))) < 1e-15);
}

TEST_CASE("FOTS: no contact gives zero; a centred press is an outward symmetric dilation", "[models][fots]") {
  for (const std::string id : {"fots", "fots-reimpl"}) {
    auto m = make_model(id, test_sensor(), sphere_indenter(4e-3));
    CHECK(max_norm(run(*m, sphere_pose(4e-3, 0, 0, -0.2e-3))) == 0.0);
    const auto d = run(*m, sphere_pose(4e-3, 0, 0, 1e-3));
    CHECK(d[marker_at(0, 0)].norm() < kPxTol);
    for (int dr = -3; dr <= 3; ++dr)
      for (int dc = -4; dc <= 4; ++dc) {
        const Vec2 v = d[marker_at(dc, dr)];
        CHECK((d[marker_at(-dc, dr)] - Vec2(-v.x(), v.y())).norm() < kPxTol);
        CHECK((d[marker_at(dc, -dr)] - Vec2(v.x(), -v.y())).norm() < kPxTol);
        if (dc == 0 && dr == 0) continue;
        CHECK(v.dot(Vec2(dc, dr)) > 0);
        if (dc == 0 || dr == 0 || std::abs(dc) == std::abs(dr)) CHECK(std::abs(v.x() * dr - v.y() * dc) < kPxTol);
      }
  }
}

TEST_CASE("FOTS original: dilation value of a neighbour marker", "[models][fots]") {
  // Sphere R = 4 mm pressed d = 1 mm: in-contact markers (0,0) h0 = 1 mm and (+-1,0), (0,+-1) with
  // h1 = R - sqrt(p^2 + (R-d)^2) (mm). Marker (1,0) at 33 px: x' - x = h0 33 W(33^2) + h1 [66 W(66^2) +
  // 2 * 33 W(2 * 33^2)], W(r2) = exp(-0.00125 r2); the shear and twist are zero (no motion yet).
  auto m = make_model("fots", test_sensor(), sphere_indenter(4e-3));
  run(*m, sphere_pose(4e-3, 0, 0, -0.1e-3));
  const auto d = run(*m, sphere_pose(4e-3, 0, 0, 1e-3));
  const double p = kPitchM, h1 = (4e-3 - std::sqrt(p * p + 9e-6)) * 1e3;
  auto W = [](double r2) { return std::exp(-0.00125 * r2); };
  const double px = 33.0 * (kPxPerM * 1e-3) / (1 / 0.0634);  // 33 px at the camera scale
  const double expected = 1.0 * px * W(px * px) + h1 * (2 * px * W(4 * px * px) + 2 * px * W(2 * px * px));
  CHECK(d[marker_at(1, 0)].x() == Approx(expected).epsilon(1e-9));
}

TEST_CASE("FOTS original: integer-pixel shear from the origin's travel since first contact", "[models][fots]") {
  // Slide 0.5 mm in x: s = int(0.5e-3 * 15772.87) = int(7.886) = 7 px; G = (int(159.5), int(119.5)) =
  // (159, 119). The centre marker (159.5, 119.5) moves by (7, 0) exp(-0.00021 * 0.5).
  for (bool integer : {true, false}) {
    auto m = fots_without_dilation("fots", box_indenter(kBox));
    ParamSet p = m->params();
    p.set("integer_px", integer ? 1 : 0);
    m->set_params(p);
    run(*m, box_pose(kBox, 0, 0, 0.1e-3));
    CHECK(max_norm(run(*m, box_pose(kBox, 0, 0, -0.5e-3))) < kPxTol);
    const auto d = run(*m, box_pose(kBox, 0.5e-3, 0, -0.5e-3));
    const double s = integer ? 7.0 : 0.5e-3 * kPxPerM;
    const double r2 = integer ? 0.5 : 0.0;
    CHECK(d[marker_at(0, 0)].x() == Approx(s * std::exp(-0.00021 * r2)).epsilon(1e-12));
    CHECK(std::abs(d[marker_at(0, 0)].y()) < kPxTol);
  }
}

TEST_CASE("FOTS: counter-clockwise twist moves markers counter-clockwise; original clips at 50 deg", "[models][fots]") {
  for (const std::string id : {"fots", "fots-reimpl"}) {
    auto m = fots_without_dilation(id, box_indenter(kBox));
    run(*m, box_pose(kBox, 0, 0, 0.1e-3));
    run(*m, box_pose(kBox, 0, 0, -0.5e-3));
    const auto d = run(*m, box_pose(kBox, 0, 0, -0.5e-3, 0.2));
    CHECK(d[marker_at(1, 0)].y() > 0);
    CHECK(d[marker_at(0, 1)].x() < 0);
    CHECK(d[marker_at(-1, 0)].y() < 0);
  }
  // Original: a 70 deg twist is clipped to 50 deg. Only the centre marker is inside a 1 mm box, at
  // every angle, so contact persists and the dilation (disabled) is unaffected.
  auto a = fots_without_dilation("fots", box_indenter(1e-3, 1));
  auto b = fots_without_dilation("fots", box_indenter(1e-3, 1));
  for (auto* m : {a.get(), b.get()}) {
    run(*m, box_pose(1e-3, 0, 0, 0.1e-3));
    run(*m, box_pose(1e-3, 0, 0, -0.3e-3));
  }
  const auto d70 = run(*a, box_pose(1e-3, 0, 0, -0.3e-3, 70 * std::numbers::pi / 180));
  const auto d50 = run(*b, box_pose(1e-3, 0, 0, -0.3e-3, 50 * std::numbers::pi / 180));
  for (int j = 0; j < kMiniMarkers; ++j) CHECK((d70[j] - d50[j]).norm() < kPxTol);
  CHECK(max_norm(d50) > 0.1);
}

TEST_CASE("FOTS: rolling a sphere about its centre gives no shear or twist", "[models][fots]") {
  for (const std::string id : {"fots", "fots-reimpl"}) {
    auto m = make_model(id, test_sensor(), sphere_indenter(4e-3));
    run(*m, sphere_pose(4e-3, 0, 0, -0.1e-3));
    const auto pressed = run(*m, sphere_pose(4e-3, 0, 0, 0.8e-3));
    const auto rolled = run(*m, sphere_pose(4e-3, 0, 0, 0.8e-3, rotation_about(Vec3(1, 2, 0).normalized(), 0.2)));
    if (id == "fots") {
      for (int j = 0; j < kMiniMarkers; ++j) CHECK((rolled[j] - pressed[j]).norm() < kPxTol);
    } else {
      // Reimpl: the anchor c is the patch centre (0, 0, -(R - d)) below the sphere centre, so a roll
      // moves it in-plane: that is the Reimpl's contact-anchored shear, not a twist.
      CHECK(max_norm(rolled) > 0);
    }
  }
}

TEST_CASE("FOTS Reimpl: shear value, anchored at the contact-patch centre", "[models][fots]") {
  // Box centred: the 9 markers inside are symmetric, c_I = (0, 0, c_z) so G = (0, 0). Slide 0.5 mm:
  // S_j = kappa_s (0.5 mm, 0) exp(-lambda_s |m_j|).
  auto m = fots_without_dilation("fots-reimpl", box_indenter(kBox));
  run(*m, box_pose(kBox, 0, 0, 0.1e-3));
  run(*m, box_pose(kBox, 0, 0, -0.5e-3));
  const auto d = run(*m, box_pose(kBox, 0.5e-3, 0, -0.5e-3));
  for (int dr = -3; dr <= 3; ++dr)
    for (int dc = -4; dc <= 4; ++dc) {
      const double r = kPitchM * std::hypot(dc, dr);
      const double expected = kPxPerM * 0.5e-3 * std::exp(-203.3439 * r);
      CHECK(d[marker_at(dc, dr)].x() == Approx(expected).epsilon(1e-9));
      CHECK(std::abs(d[marker_at(dc, dr)].y()) < kPxTol);
    }
  // Contact lost: zero, and the next contact starts a new history (a pure press shows no shear).
  CHECK(max_norm(run(*m, box_pose(kBox, 0.5e-3, 0, 0.2e-3))) == 0.0);
  const auto again = run(*m, box_pose(kBox, 0.5e-3, 0, -0.5e-3));
  CHECK(max_norm(again) < kPxTol);
}

TEST_CASE("FOTS Reimpl: the anchor is set when the normal approach ends (the authors' 'after the grasp')",
          "[models][fots]") {
  // A 4 mm sphere pressed in two steps, 0.2 mm then 0.8 mm, then rolled by 0.2 rad about x_E through its
  // centre. The patch centre is on the gel plane, h = R - depth below the sphere's centre: c_I = (0, 0, -h).
  // At 0.2 mm only the centre marker is inside (contact radius sqrt(2 R d) = 1.26 mm < 2.09 mm pitch), at
  // 0.8 mm five (2.53 mm), all centred: G = (0, 0). The roll moves C in-plane by R_x(t) c_I - c_I =
  // (0, h sin t, .), with no twist (the rotation vector has no z part), so at the centre marker
  //   S = kappa_s (0, h sin t),  h = 3.2 mm (anchored at the end of the press) or 3.8 mm (at first contact).
  constexpr double kR = 4e-3, kRoll = 0.2;
  for (const double grasp : {1.0, 0.0}) {
    auto m = fots_without_dilation("fots-reimpl", sphere_indenter(kR));
    ParamSet p = m->params();
    p.set("anchor_grasp", grasp);
    m->set_params(p);
    run(*m, sphere_pose(kR, 0, 0, -0.1e-3));
    run(*m, sphere_pose(kR, 0, 0, 0.2e-3));
    const auto pressed = run(*m, sphere_pose(kR, 0, 0, 0.8e-3));
    CHECK(max_norm(pressed) < kPxTol);  // a pure press: no shear, whichever the anchor
    const auto rolled = run(*m, sphere_pose(kR, 0, 0, 0.8e-3, Rx(kRoll)));
    const double h = kR - (grasp > 0 ? 0.8e-3 : 0.2e-3);
    INFO("anchor_grasp " << grasp);
    CHECK(std::abs(rolled[marker_at(0, 0)].x()) < kPxTol);
    CHECK(rolled[marker_at(0, 0)].y() == Approx(kPxPerM * h * std::sin(kRoll)).epsilon(1e-9));
  }
}

}  // namespace test_fots
