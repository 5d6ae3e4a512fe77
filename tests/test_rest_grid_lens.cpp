// The rest grid's lens (core/loop/rest_grid_lens.hpp): the lattice indices assigned from the rest positions
// alone, and rest_i = D_k1(o + A n_i) fitted, D the lens_distortion effect's convention.
#include <catch2/catch.hpp>

#include "mini_grid.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include "core/effects/effects.hpp"
#include "core/loop/rest_grid_lens.hpp"
#include "core/sensor/sensor.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_rest_grid_lens {

using sbtest::kMiniMarkers;

using sb::Vec2;

namespace {

// The GelSight Mini camera: 320 x 240 px, principal point (159.5, 119.5), half-diagonal 200 px.
sb::Camera camera() { return sb::make_default_sensor().camera; }

// A rows x cols lattice at `pitch` px turned by `angle` about the principal point, seen through D_k1.
std::vector<Vec2> lattice(int rows, int cols, double pitch, double angle, double k1) {
  const sb::Camera c = camera();
  const Eigen::Rotation2Dd R(angle);
  std::vector<Vec2> out;
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) {
      const Vec2 n(j - 0.5 * (cols - 1), i - 0.5 * (rows - 1));
      out.push_back(sb::lens_distort_px(c, k1, c.principal_px + R * (pitch * n)));
    }
  return out;
}

void add_noise(std::vector<Vec2>* p, double sigma, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0.0, sigma);
  for (auto& v : *p) {
    const double dx = n(rng);  // two statements: argument order is unspecified
    v += Vec2(dx, n(rng));
  }
}

}  // namespace

TEST_CASE("rest grid lens: D is the lens_distortion effect's map, a corner marker by hand", "[rest_grid_lens]") {
  // A 3 x 3 grid at 33 px about c = (159.5, 119.5), k1 = -0.15. The corner q = (33, 33): r^2 = 2178 / 200^2 =
  // 0.05445, 1 + k1 r^2 = 0.9918325, so it is imaged at c + 33 x 0.9918325 (1, 1) = (192.2304725, 152.2304725).
  constexpr double kHandTolPx = 1e-9;
  const Vec2 corner(192.2304725, 152.2304725);
  CHECK((sb::lens_distort_px(camera(), -0.15, Vec2(192.5, 152.5)) - corner).norm() < kHandTolPx);
  // The effect maps a marker's displacement d as D(m + d) - D(m): at m = c (D(c) = c) it is D(c + d) - c.
  sb::Sensor s = sb::make_default_sensor();
  const std::size_t centre = 3 * 9 + 4;  // row 3, column 4 of the 7 x 9 grid: the principal point
  REQUIRE((s.markers_rest_px[centre] - s.camera.principal_px).norm() < kHandTolPx);
  auto lens = sb::make_effect("lens_distortion");
  sb::ParamSet p = lens->params();
  p.set("k1", -0.15);
  lens->set_params(p);
  std::vector<Vec2> field(s.markers_rest_px.size(), Vec2::Zero());
  field[centre] = Vec2(33, 33);
  sb::EffectContext ctx;
  ctx.sensor = &s;
  lens->apply(ctx, field);
  CHECK((field[centre] - (corner - s.camera.principal_px)).norm() < kHandTolPx);

  // The fit on that 3 x 3 grid gives the corner back at its lattice node (1, 1) (the steps at the seed are
  // +x and +y: the shorter of two equal steps is the one with the smaller x, turned to x >= 0).
  const auto fit = sb::rest_grid_lens(camera(), lattice(3, 3, 33.0, 0.0, -0.15));
  REQUIRE(fit.is_lattice);
  CHECK(fit.markers_used == 9);
  CHECK(std::abs(fit.k1 + 0.15) < 1e-9);
  CHECK((sb::rest_grid_node_px(camera(), fit, Eigen::Vector2i(1, 1)) - corner).norm() < kHandTolPx);
}

TEST_CASE("rest grid lens: a perfect 7 x 9 lattice at 33 px has no lens", "[rest_grid_lens]") {
  // Exact data: the fit ends at its start (k1 = 0, the affine least squares) up to rounding.
  constexpr double kExactTol = 1e-9;
  const auto fit = sb::rest_grid_lens(camera(), sb::make_default_sensor().markers_rest_px);
  INFO(sb::describe(fit));
  REQUIRE(fit.is_lattice);
  CHECK(fit.markers_used == kMiniMarkers);
  CHECK(std::set<int>{fit.span.x(), fit.span.y()} == std::set<int>{7, 9});
  CHECK(std::abs(fit.k1) < kExactTol);
  CHECK(fit.rms_px < kExactTol);
  CHECK(fit.pitch_px == Approx(33.0).epsilon(kExactTol));
  CHECK(fit.pitch_long_px == Approx(33.0).epsilon(kExactTol));
}

TEST_CASE("rest grid lens: k1 = -0.15 with 0.05 px noise", "[rest_grid_lens]") {
  // k1's standard error for this lattice: J = d rest / d(o, A, k1) at the truth (the k1 column is q r^2, the
  // others D'(u) times the affine columns); sqrt((J^T J)^-1_k1k1) = 0.0057 per px of noise (evaluated once
  // by hand-written code: 0.0070 at k1 = 0, 0.0057 at -0.15), so 0.00028 at sigma = 0.05 px. The tolerance
  // is 7 such errors; the fit's own reported error must be that size (within a factor 2: one noise draw).
  constexpr double kExpectedStderr = 0.00028;
  constexpr double kK1Tol = 7 * kExpectedStderr;
  auto rest = lattice(7, 9, 33.0, 0.0, -0.15);
  // The corner (r = 165 / 200) moves by k1 r^2 |q| = -16.8 px: a quarter of the way to its inner neighbour.
  CHECK((rest.front() - camera().principal_px).norm() == Approx(165.0 * (1 - 0.15 * 0.680625)).epsilon(1e-12));
  add_noise(&rest, 0.05, 16);
  const auto fit = sb::rest_grid_lens(camera(), rest);
  INFO(sb::describe(fit));
  REQUIRE(fit.is_lattice);
  CHECK(fit.markers_used == kMiniMarkers);
  CHECK(std::abs(fit.k1 + 0.15) < kK1Tol);
  CHECK(fit.k1_stderr > 0.5 * kExpectedStderr);
  CHECK(fit.k1_stderr < 2.0 * kExpectedStderr);
  // The residual is the noise: RMS of a 2-D Gaussian of 0.05 px per component is 0.0707 px, less the 7
  // fitted parameters' share (sqrt(119 / 126)): 0.069 px; one draw within 20 %.
  CHECK(fit.rms_px == Approx(0.069).epsilon(0.2));
  CHECK(fit.pitch_px == Approx(33.0).epsilon(0.001));
}

TEST_CASE("rest grid lens: a rotated lattice in shuffled order, with lost markers", "[rest_grid_lens]") {
  constexpr double kExactTol = 1e-9;
  auto rest = lattice(7, 9, 31.0, 0.35, 0.08);
  std::mt19937_64 rng(3);
  std::shuffle(rest.begin(), rest.end(), rng);
  const auto fit = sb::rest_grid_lens(camera(), rest);
  INFO(sb::describe(fit));
  REQUIRE(fit.is_lattice);
  CHECK(fit.markers_used == kMiniMarkers);
  CHECK(std::abs(fit.k1 - 0.08) < kExactTol);
  CHECK(fit.pitch_px == Approx(31.0).epsilon(kExactTol));
  // Every marker lies on its own node: the indices are the lattice's, whatever the storage order.
  for (std::size_t i = 0; i < rest.size(); ++i)
    CHECK((sb::rest_grid_node_px(camera(), fit, fit.indices.index[i]) - rest[i]).norm() < 1e-6);

  SECTION("NaN markers are skipped, a missing one leaves a hole the growth goes round") {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (std::size_t i : {0, 5, 17, 40}) rest[i] = Vec2(nan, nan);
    rest.erase(rest.begin() + 22);
    const auto holed = sb::rest_grid_lens(camera(), rest);
    INFO(sb::describe(holed));
    REQUIRE(holed.is_lattice);
    CHECK(holed.markers_used == 58);
    CHECK(std::abs(holed.k1 - 0.08) < kExactTol);
    CHECK_FALSE(holed.indices.assigned[0]);
  }
}

TEST_CASE("rest grid lens: what is not a lattice", "[rest_grid_lens]") {
  SECTION("scattered points") {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<Vec2> pts;
    for (int i = 0; i < kMiniMarkers; ++i) {
      const double x = 320 * u(rng);
      pts.emplace_back(x, 240 * u(rng));
    }
    const auto fit = sb::rest_grid_lens(camera(), pts);
    INFO(sb::describe(fit));
    CHECK_FALSE(fit.is_lattice);
    CHECK_FALSE(fit.why_not.empty());
  }
  SECTION("pins on rings (the TacTip's pattern): 6 i pins equally spaced on ring i") {
    // Ring 2's edge midpoints sit at 2 pitches instead of the hexagonal lattice's sqrt(3): 0.27 pitch off,
    // and further out the rings drift from any lattice.
    std::vector<Vec2> pins{camera().principal_px};
    for (int ring = 1; ring <= 5; ++ring)
      for (int k = 0; k < 6 * ring; ++k) {
        const double phi = 2 * M_PI * k / (6.0 * ring);
        pins.push_back(camera().principal_px + 20.0 * ring * Vec2(std::cos(phi), std::sin(phi)));
      }
    const auto fit = sb::rest_grid_lens(camera(), pins);
    INFO(sb::describe(fit));
    CHECK_FALSE(fit.is_lattice);
  }
  SECTION("a line of markers") {
    std::vector<Vec2> line;
    for (int i = 0; i < 12; ++i) line.push_back(camera().principal_px + Vec2(20.0 * (i - 6), 0));
    CHECK_FALSE(sb::rest_grid_lens(camera(), line).is_lattice);
  }
  SECTION("too few markers") {
    const auto fit = sb::rest_grid_lens(camera(), lattice(2, 3, 33.0, 0.0, 0.0));
    CHECK_FALSE(fit.is_lattice);
    CHECK(fit.markers_used == 6);
  }
}

}  // namespace test_rest_grid_lens
