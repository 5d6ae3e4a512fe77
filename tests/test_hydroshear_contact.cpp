// HydroShear's contact variant (model "hydroshear-contact"): layer + stick with two more terms,
//   far field:  exp(-l_s r^2) + beta_s exp(-l_s2 r^2) + beta_s3 exp(-l_s3 r^2),
//   following:  a_i = o_i + u_i + c,  c = -follow sum_k w_k u_k^t / sum_k w_k   (w_k = E u_n,k),
//   anisotropy: the far term's v_i -> v_i + aniso_s3 l_s3 d (d . v_i),  d = m - a_i in the plane,
// neither of which changes the state. The expected fields are built by hand from plain HydroShear runs:
// the shear part S of a run is isolated by doubling its gain (the dilation does not depend on kappa_s),
//   S = F(kappa_s = 2k) - F(kappa_s = k),
// and the shifted sum is formed here over HydroShearBatch::tracked():
//   S_j = kappa_s sum_i w_i (-K u_i^xy) exp(-l_s |m_j - (o_i + u_i + c)|^2).
#include <algorithm>
#include <catch2/catch.hpp>

#include "hydroshear_fixtures.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_hydroshear_contact {

using namespace sbtest;

namespace {

constexpr double kPxTol = 1e-9;  // px: the same sums in another order
// The contact variant sums its terms in single precision (2^-24 per rounding, a few roundings per operand,
// 8-lane float partial sums over at most 96 points, then double): relative to the largest marker motion of
// the field, against the double sums of the models it is compared with.
constexpr double kFloatRel = 1e-6;

// The contact variant with the authors' values and the given extra terms; the layer, the stick and the far
// field's anisotropy off.
ParamSet contact_params(double beta_s3, double lambda_s3, double follow, double lambda_s = 0) {
  ParamSet d = default_params("hydroshear");
  if (lambda_s > 0) d.set("lambda_s", lambda_s);
  ParamSet p = default_params("hydroshear-contact");
  for (const auto& spec : d.specs()) p.set(spec.name, d.get(spec.name));
  p.set("beta_s", 0), p.set("stick_sat", 0);
  p.set("beta_s3", beta_s3), p.set("lambda_s3", lambda_s3), p.set("follow", follow), p.set("aniso_s3", 0);
  return p;
}

// The shear part of a parameter set's field (doubling kappa_s doubles it and leaves the dilation).
std::vector<Vec2> shear_part(ParamSet p, const std::shared_ptr<const Sensor>& sensor) {
  const auto once = hs_path_field(p, sensor);
  p.set("kappa_s", 2 * p.get("kappa_s"));
  const auto twice = hs_path_field(p, sensor);
  std::vector<Vec2> s(once.size());
  for (std::size_t j = 0; j < s.size(); ++j) s[j] = twice[j] - once[j];
  return s;
}

// The test sensor with its markers moved off the grid (up to 0.3 mm in the plane, up to 0.2 mm below the surface,
// deterministically): the shear sum then takes its path for markers anywhere (the TacTip's pins), one point
// against every marker, instead of the grid's factored Gaussians.
std::shared_ptr<const Sensor> off_grid_sensor() {
  auto s = std::make_shared<Sensor>(*test_sensor());
  for (std::size_t j = 0; j < s->p_EM.size(); ++j) {
    const double t = static_cast<double>(j);
    s->p_EM[j] += Vec3(0.3e-3 * std::sin(1.7 * t), 0.3e-3 * std::cos(2.3 * t), -0.1e-3 * (1 + std::sin(0.9 * t)));
  }
  return s;
}

// The grid's sensor or the same markers off the grid (GENERATE: each test case runs both).
std::shared_ptr<const Sensor> either_sensor(bool off_grid) { return off_grid ? off_grid_sensor() : test_sensor(); }

}  // namespace

TEST_CASE("hydroshear-contact with no far field and no following is layer + stick, to single precision",
          "[models][hydroshear_contact]") {
  ParamSet ls = default_params("hydroshear-layer-stick");
  ParamSet p = default_params("hydroshear-contact");
  for (const auto& spec : ls.specs()) p.set(spec.name, ls.get(spec.name));
  p.set("beta_s3", 0), p.set("follow", 0);  // the anisotropy then has no term to act on
  const auto contact = hs_path_field(p);
  const auto plain = hs_path_field(ls);
  REQUIRE(contact.size() == plain.size());
  for (std::size_t j = 0; j < contact.size(); ++j) {
    INFO("marker " << j);
    CHECK((contact[j] - plain[j]).norm() < kPxTol + kFloatRel * max_norm(plain));
  }
  // In double (float32 = 0) the same sums in another order.
  p.set("float32", 0);
  const auto exact = hs_path_field(p);
  for (std::size_t j = 0; j < exact.size(); ++j) {
    INFO("marker " << j);
    CHECK((exact[j] - plain[j]).norm() < kPxTol);
  }
  CHECK(max_norm(plain) > 0.1);  // the path moves markers: the comparison is not of zeros
}

TEST_CASE("hydroshear-contact's far field adds a third Gaussian linearly", "[models][hydroshear_contact]") {
  const ParamSet d = default_params("hydroshear");
  const double beta_s3 = 0.3, ls3 = 2e4;  // 1/sqrt(2 l_s3) = 5 mm wide: it reaches every marker
  const auto far = hs_path_field(contact_params(beta_s3, ls3, 0));
  const auto base = hs_path_field(d);
  ParamSet wide = d;
  wide.set("lambda_s", ls3);
  const auto S3 = shear_part(wide, test_sensor());
  double far_s = 0;
  for (std::size_t j = 0; j < far.size(); ++j) {
    INFO("marker " << j);
    CHECK((far[j] - (base[j] + beta_s3 * S3[j])).norm() < kPxTol + kFloatRel * max_norm(far));
    far_s = std::max(far_s, beta_s3 * S3[j].norm());
  }
  CHECK(far_s > 0.01);  // the term moves markers on this path
}

TEST_CASE("hydroshear-contact's following moves every kernel by follow times the weighted mean stuck state",
          "[models][hydroshear_contact]") {
  // A kernel 1.3 mm wide (1/sqrt(2 l_s)), so a shift of a few tenths of a millimetre shows in the field.
  constexpr double kLambdaS = 3e5;
  ParamSet d = default_params("hydroshear");
  d.set("lambda_s", kLambdaS);
  const double ks = d.get("kappa_s"), ls = d.get("lambda_s"), E = d.get("E"), K = d.get("K");
  constexpr double kFollow = 0.8;
  const bool off_grid = GENERATE(false, true);
  INFO((off_grid ? "markers off the grid" : "markers on the grid"));
  const auto sensor = either_sensor(off_grid);
  // The state, from a plain run (the following does not change it).
  HydroShearBatch plain(sensor, hs_box(), 1, d);
  (void)hs_path_field(plain);
  const auto points = plain.tracked(0);
  REQUIRE(!points.empty());
  double sw = 0;
  Vec2 swu = Vec2::Zero();
  for (const HydroShearPoint& t : points) {
    sw += E * t.u_n;
    swu += E * t.u_n * t.u_E.head<2>();  // the normal is +z: u_E's in-plane part is u_t
  }
  const Vec2 c = -kFollow * swu / sw;
  CHECK(c.norm() > 0.1e-3);  // the box slid 0.32 mm while stuck: the shift is not a rounding
  // The shifted sum by hand.
  const Pose X = hs_box_path().back();
  std::vector<Vec2> expected(sensor->p_EM.size(), Vec2::Zero());
  for (const HydroShearPoint& t : points) {
    Vec3 a = X * hs_box()->samples.p_IS[t.index] + t.u_E;
    a.head<2>() += c;
    const Vec2 v = -E * t.u_n * K * t.u_E.head<2>();
    for (std::size_t j = 0; j < expected.size(); ++j)
      expected[j] += ks * v * std::exp(-ls * (sensor->p_EM[j] - a).squaredNorm());
  }
  const auto S = shear_part(contact_params(0, 3e4, kFollow, kLambdaS), sensor);
  const auto S0 = shear_part(contact_params(0, 3e4, 0, kLambdaS), sensor);
  double moved = 0;
  for (std::size_t j = 0; j < S.size(); ++j) {
    INFO("marker " << j);
    CHECK((S[j] - expected[j]).norm() < 1e-6);  // px: the sum over ~50 points in another order
    moved = std::max(moved, (S[j] - S0[j]).norm());
  }
  // The following changes the field on this path (by 4 % of its largest shear; the tolerance above is
  // a thousandth of that change).
  CHECK(moved > 0.02 * max_norm(S0));
}

// The far field's anisotropy, by hand: with everything else fixed, turning it on adds
//   kappa_s sum_i beta_s3 exp(-l_s3 |m - a_i|^2) aniso l_s3 d_i (d_i . v_i),  d_i = (m - a_i) in the plane,
// v_i = -E u_n,i K u_i^xy (the authors' weight and force). The factored sum splits d d^T into variants of
// the axes' factors, in single precision (add_term_single); this sums it point by point in double.
TEST_CASE("hydroshear-contact's far-field anisotropy adds aniso l d (d . v) to each point's term",
          "[models][hydroshear_contact]") {
  constexpr double kBeta3 = 0.3, kLambda3 = 2e4, kAniso = 3;  // 5 mm wide: it reaches every marker
  const ParamSet d = default_params("hydroshear");
  const double ks = d.get("kappa_s"), E = d.get("E"), K = d.get("K");
  const bool off_grid = GENERATE(false, true);
  INFO((off_grid ? "markers off the grid" : "markers on the grid"));
  const auto sensor = either_sensor(off_grid);
  HydroShearBatch plain(sensor, hs_box(), 1, d);
  (void)hs_path_field(plain);
  const auto points = plain.tracked(0);
  REQUIRE(!points.empty());
  const Pose X = hs_box_path().back();
  std::vector<Vec2> expected(sensor->p_EM.size(), Vec2::Zero());
  for (const HydroShearPoint& t : points) {
    const Vec3 a = X * hs_box()->samples.p_IS[t.index] + t.u_E;
    const Vec2 v = -E * t.u_n * K * t.u_E.head<2>();
    for (std::size_t j = 0; j < expected.size(); ++j) {
      const Vec3 m = sensor->p_EM[j];
      const Vec2 dj = (m - a).head<2>();
      expected[j] += ks * kBeta3 * std::exp(-kLambda3 * (m - a).squaredNorm()) * kAniso * kLambda3 * dj * dj.dot(v);
    }
  }
  ParamSet p = contact_params(kBeta3, kLambda3, 0);
  const auto iso = hs_path_field(p, sensor);
  p.set("aniso_s3", kAniso);
  const auto aniso = hs_path_field(p, sensor);
  double largest = 0;
  for (std::size_t j = 0; j < aniso.size(); ++j) {
    INFO("marker " << j);
    CHECK((aniso[j] - iso[j] - expected[j]).norm() < kPxTol + kFloatRel * max_norm(aniso));
    largest = std::max(largest, expected[j].norm());
  }
  CHECK(largest > 1e-4 * max_norm(iso));  // the term is not zero on this path
  INFO("largest anisotropic part " << largest << " px of a field of " << max_norm(iso));
}

TEST_CASE("a step without a field advances the state exactly as one with it", "[models][hydroshear]") {
  // The TacTip's samples are scored at their last frame only: the frames before are stepped with an empty
  // field (no shear sum, no dilation). The field at the end must not depend on that, bit for bit.
  for (const std::string id : {"hydroshear", "hydroshear-layer", "hydroshear-stick", "hydroshear-contact"}) {
    ParamSet p = default_params(id);
    if (p.index_of("follow") >= 0) p.set("follow", 0.5);
    HydroShearBatch every(test_sensor(), hs_box(), 1, p), last_only(test_sensor(), hs_box(), 1, p);
    const std::vector<Vec2> expected = hs_path_field(every);
    const auto path = hs_box_path();
    std::vector<Vec2> disp(last_only.markers());
    for (std::size_t k = 0; k < path.size(); ++k)
      last_only.step(std::span<const Pose>(&path[k], 1), 0.01,
                     k + 1 == path.size() ? std::span<Vec2>(disp) : std::span<Vec2>(), {});
    INFO(id);
    CHECK(disp == expected);
  }
}

TEST_CASE("a field-only parameter changed mid-path gives the field of a path run with it throughout",
          "[models][hydroshear]") {
  // The fit's finite differences over a field-only parameter replay only the scored frames from a copy of the
  // model taken before them (core/calibration/fit.cpp); that is exact iff the parameter never reaches the state.
  const auto path = hs_box_path();
  for (const std::string id : {"hydroshear", "hydroshear-contact"}) {
    const ParamSet table = default_params(id);
    for (std::size_t i = 0; i < table.size(); ++i) {
      const ParamSpec& spec = table.specs()[i];
      if (!spec.field_only || spec.name == "float32") continue;
      ParamSet changed = table;
      changed.set(i, std::clamp(table[i] == 0 ? 0.5 * spec.max : 1.3 * table[i], spec.min, spec.max));
      HydroShearBatch throughout(test_sensor(), hs_box(), 1, changed), switched(test_sensor(), hs_box(), 1, table);
      const std::vector<Vec2> expected = hs_path_field(throughout);
      std::vector<Vec2> disp(switched.markers());
      for (std::size_t k = 0; k < path.size(); ++k) {
        if (k + 1 == path.size()) switched.set_params(changed);
        switched.step(std::span<const Pose>(&path[k], 1), 0.01, disp, {});
      }
      INFO(id << " " << spec.name);
      CHECK(disp == expected);
    }
  }
}

}  // namespace test_hydroshear_contact
