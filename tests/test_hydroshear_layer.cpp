// HydroShear with the bonded-layer kernel (model "hydroshear-layer"): the shear kernel gains a near-field
// term, exp(-l_s r^2) -> exp(-l_s r^2) + beta_s exp(-l_s2 r^2). The field is linear in its kernel, so the
// expected field is built from plain HydroShear runs:
//   layer = F(l_s) + beta_s S(l_s2),
// where the shear part S(l) is isolated by doubling its gain (the dilation does not depend on kappa_s):
//   S(l) = F(kappa_s = 2k, lambda_s = l) - F(kappa_s = k, lambda_s = l).
#include <catch2/catch.hpp>

#include "model_fixtures.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_hydroshear_layer {

using namespace sbtest;

namespace {

constexpr double kPxTol = 1e-9;  // px: the same sums in another order
constexpr double kBox = 6e-3;    // box indenter side: it covers markers, so the dilation acts

// The field along a press, a slide and a twist of the box (stick and slip, shear and dilation).
std::vector<Vec2> path_field(const std::string& id, const ParamSet& p) {
  auto m = make_model(id, test_sensor(), box_indenter(kBox, 7, 0.8e-3));
  m->set_params(p);
  run(*m, box_pose(kBox, 0, 0, 0.1e-3));
  run(*m, box_pose(kBox, 0, 0, -0.4e-3));
  run(*m, box_pose(kBox, 0.3e-3, 0.1e-3, -0.4e-3));
  return run(*m, box_pose(kBox, 0.3e-3, 0.1e-3, -0.4e-3, 0.04));
}

std::vector<Vec2> hs_field(double lambda_s, double kappa_s) {
  ParamSet p = default_params("hydroshear");
  p.set("lambda_s", lambda_s), p.set("kappa_s", kappa_s);
  return path_field("hydroshear", p);
}

}  // namespace

TEST_CASE("hydroshear-layer with beta = 0 is HydroShear, bit for bit", "[models][hydroshear_layer]") {
  ParamSet p = default_params("hydroshear-layer");
  p.set("beta_s", 0);
  const auto layer = path_field("hydroshear-layer", p);
  const auto plain = path_field("hydroshear", default_params("hydroshear"));
  REQUIRE(layer.size() == plain.size());
  for (std::size_t j = 0; j < layer.size(); ++j) CHECK(layer[j] == plain[j]);
  CHECK(max_norm(plain) > 0.1);  // the path moves markers: the comparison is not of zeros
}

TEST_CASE("hydroshear-layer adds the shear kernel's near-field term linearly", "[models][hydroshear_layer]") {
  const ParamSet d = default_params("hydroshear");
  const double ls = d.get("lambda_s"), ks = d.get("kappa_s");
  const double beta_s = 2.5, ls2 = 3e5;  // near field 1/sqrt(2 l_s2) = 1.3 mm wide: it reaches the markers
  ParamSet p = default_params("hydroshear-layer");
  p.set("beta_s", beta_s), p.set("lambda_s2", ls2);
  const auto layer = path_field("hydroshear-layer", p);

  const auto base = hs_field(ls, ks);
  const auto s2_twice = hs_field(ls2, 2 * ks), s2_once = hs_field(ls2, ks);
  double near_s = 0;
  for (std::size_t j = 0; j < layer.size(); ++j) {
    const Vec2 S2 = s2_twice[j] - s2_once[j];
    INFO("marker " << j);
    CHECK((layer[j] - (base[j] + beta_s * S2)).norm() < kPxTol);
    near_s = std::max(near_s, (beta_s * S2).norm());
  }
  CHECK(near_s > 0.01);  // the near-field term acts on this path (the check is not of zeros)
}

}  // namespace test_hydroshear_layer
