// HydroShear with the stick zone (models "hydroshear-stick", "hydroshear-layer-stick"): the shear sum
// saturates where the contact's weights pile up,
//   M_s(m_j) -> M_s(m_j) / (1 + s W_j),   W_j = sum_i w_i exp(-lambda_s |m_j - a_i|^2),
// w_i = E u_n,i (the authors' weight), a_i = o_i + u_i the anchor. The state is HydroShear's, so the expected
// field is built from a plain HydroShear run and its tracked points:
//   shear part S = F(kappa_s = 2k) - F(kappa_s = k) (the dilation does not depend on kappa_s),
//   dilation D = F(k) - S,   stick = D + S / (1 + s W),
// with W summed here by hand over HydroShearBatch::tracked().
#include <catch2/catch.hpp>

#include "hydroshear_fixtures.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_hydroshear_stick {

using namespace sbtest;

namespace {

constexpr double kPxTol = 1e-9;  // px: the same sums in another order

}  // namespace

TEST_CASE("hydroshear-stick with s = 0 is HydroShear, bit for bit", "[models][hydroshear_stick]") {
  ParamSet p = default_params("hydroshear-stick");
  p.set("stick_sat", 0);
  auto m = make_model("hydroshear-stick", test_sensor(), hs_box());
  auto h = make_model("hydroshear", test_sensor(), hs_box());
  m->set_params(p);
  std::vector<Vec2> stick, plain;
  for (const Pose& X : hs_box_path()) stick = run(*m, X), plain = run(*h, X);
  REQUIRE(stick.size() == plain.size());
  for (std::size_t j = 0; j < stick.size(); ++j) CHECK(stick[j] == plain[j]);
  CHECK(max_norm(plain) > 0.1);  // the path moves markers: the comparison is not of zeros
}

TEST_CASE("hydroshear-stick divides the shear sum by 1 + s W", "[models][hydroshear_stick]") {
  const ParamSet d = default_params("hydroshear");
  const double ks = d.get("kappa_s"), ls = d.get("lambda_s"), E = d.get("E");
  ParamSet twice = d;
  twice.set("kappa_s", 2 * ks);
  HydroShearBatch plain(test_sensor(), hs_box(), 1, d);
  const auto F = hs_path_field(plain);
  const auto F2 = hs_path_field(twice);
  // W by hand from the plain run's tracked points (the stick zone leaves the state as HydroShear's).
  const Pose X = hs_box_path().back();
  const auto sensor = test_sensor();
  std::vector<double> W(sensor->p_EM.size(), 0.0);
  for (const HydroShearPoint& t : plain.tracked(0)) {
    const Vec3 anchor = X * hs_box()->samples.p_IS[t.index] + t.u_E;
    for (std::size_t j = 0; j < W.size(); ++j)
      W[j] += E * t.u_n * std::exp(-ls * (sensor->p_EM[j] - anchor).squaredNorm());
  }
  constexpr double kSat = 2e3;  // 1/m: W reaches ~1e-3 m over this contact, so s W is of order 1
  for (const std::string id : {"hydroshear-stick", "hydroshear-layer-stick"}) {
    ParamSet p = default_params(id);
    for (const auto& spec : d.specs()) p.set(spec.name, d.get(spec.name));
    p.set("stick_sat", kSat);
    if (p.index_of("beta_s") >= 0) p.set("beta_s", 0);  // the layer's near field off: the same S
    const auto stick = hs_path_field(p);
    double largest_sW = 0;
    for (std::size_t j = 0; j < stick.size(); ++j) {
      const Vec2 S = F2[j] - F[j], D = F[j] - S;
      INFO(id << " marker " << j);
      CHECK((stick[j] - (D + S / (1 + kSat * W[j]))).norm() < kPxTol);
      largest_sW = std::max(largest_sW, kSat * W[j]);
    }
    CHECK(largest_sW > 0.3);  // the saturation acts on this path (the check is not of a factor 1)
  }
}

}  // namespace test_hydroshear_stick
