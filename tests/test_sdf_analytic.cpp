#include <catch2/catch.hpp>
#include <cmath>

#include "core/geometry/sdf.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_sdf_analytic {

using namespace sb;

namespace {
constexpr double kExact = 1e-12;  // metres: closed-form distances
constexpr double kTol = 1e-12;    // metres: the cap's distances, closed-form too (a square root and a hypot)
}  // namespace

TEST_CASE("sphere SDF is |p - c| - r with a radial gradient", "[sdf]") {
  const auto s = make_sphere_sdf(0.004, Vec3(0, 0, 0.001));
  Vec3 g;
  // (0, 0.003, 0.001) is 3 mm from the centre: phi = 3 - 4 = -1 mm, gradient +y.
  CHECK(std::abs(s->value_and_gradient(Vec3(0, 0.003, 0.001), &g) + 0.001) < kExact);
  CHECK((g - Vec3::UnitY()).norm() < kExact);
}

TEST_CASE("torus SDF measures distance to the tube's centre circle", "[sdf]") {
  const auto t = make_torus_sdf(0.006, 0.0015);
  Vec3 g;
  // On the x axis at rho = 6 mm, z = 1 mm: 1 mm from the centre circle, phi = 1 - 1.5 = -0.5 mm, grad +z.
  CHECK(std::abs(t->value_and_gradient(Vec3(0.006, 0, 0.001), &g) + 0.0005) < kExact);
  CHECK((g - Vec3::UnitZ()).norm() < kExact);
  // At the origin: distance to the circle is R, phi = R - r = 4.5 mm.
  CHECK(std::abs(t->value(Vec3::Zero()) - 0.0045) < kExact);
}

TEST_CASE("pad SDF: gel occupies z in [-thickness, 0]", "[sdf]") {
  const auto pad = make_pad_sdf(Vec2(0.02525, 0.02075), 0.0045);
  Vec3 g;
  // 0.3 mm below the centre of the surface: nearest face is the top, phi = -0.3 mm, gradient +z.
  CHECK(std::abs(pad->value_and_gradient(Vec3(0, 0, -0.0003), &g) + 0.0003) < kExact);
  CHECK((g - Vec3::UnitZ()).norm() < kExact);
  // 1 mm above the surface: +1 mm.
  CHECK(std::abs(pad->value(Vec3(0.001, 0.002, 0.001)) - 0.001) < kExact);
  // Beyond the +x edge and above: the distance to the edge line is hypot(1, 1) mm.
  CHECK(std::abs(pad->value(Vec3(0.02525 / 2 + 0.001, 0, 0.001)) - std::hypot(0.001, 0.001)) < kExact);
}

TEST_CASE("capped cylinder SDF: side, caps and rim", "[sdf]") {
  const double R = 0.004, L = 0.04;
  const auto c = make_capped_cylinder_sdf(R, L);
  Vec3 g;
  // Centre: nearest surface is the side wall (R = 4 mm < L/2 = 20 mm): phi = -4 mm.
  CHECK(std::abs(c->value(Vec3::Zero()) + R) < kExact);
  // 1 mm outside the wall at mid height: +1 mm, gradient radial.
  CHECK(std::abs(c->value_and_gradient(Vec3(0, R + 0.001, 0), &g) - 0.001) < kExact);
  CHECK((g - Vec3::UnitY()).norm() < kExact);
  // 2 mm beyond the top cap on the axis: +2 mm, gradient +z.
  CHECK(std::abs(c->value_and_gradient(Vec3(0, 0, L / 2 + 0.002), &g) - 0.002) < kExact);
  CHECK((g - Vec3::UnitZ()).norm() < kExact);
  // Past the bottom rim by (3 mm radially, 4 mm axially): distance 5 mm, gradient (3, 0, -4)/5.
  CHECK(std::abs(c->value_and_gradient(Vec3(R + 0.003, 0, -L / 2 - 0.004), &g) - 0.005) < kExact);
  CHECK((g - Vec3(0.6, 0, -0.8)).norm() < kExact);
  // Inside near the top cap: 0.5 mm below it on the axis, phi = -0.5 mm, gradient +z.
  CHECK(std::abs(c->value_and_gradient(Vec3(0, 0, L / 2 - 0.0005), &g) + 0.0005) < kExact);
  CHECK((g - Vec3::UnitZ()).norm() < kExact);
}

TEST_CASE("a transformed SDF evaluates the inner field in its own frame", "[sdf]") {
  // Sphere r = 1 mm at the origin of B; B sits at (0, 0, 5 mm) in A, rotated 90 deg about x.
  Pose X_AB = Pose::Identity();
  X_AB.linear() = Rx(M_PI / 2);
  X_AB.translation() = Vec3(0, 0, 0.005);
  const auto s = make_transformed_sdf(make_sphere_sdf(0.001), X_AB);
  Vec3 g;
  // p_A = (0, 0, 7 mm) is 2 mm from B's origin: phi = 1 mm; the gradient in A is +z.
  CHECK(std::abs(s->value_and_gradient(Vec3(0, 0, 0.007), &g) - 0.001) < kExact);
  CHECK((g - Vec3::UnitZ()).norm() < kExact);
}

TEST_CASE("spherical cap SDF: dome, rim, wall and bottom; against the cap's mesh", "[sdf]") {
  // R = 20 mm, footprint 12 mm: rim at z = -(R - sqrt(R^2 - F^2)) = -(20 - 16) = -4 mm; thickness 10 mm.
  const double R = 20e-3, F = 12e-3, T = 10e-3;
  const auto cap = make_spherical_cap_sdf(R, F, T);
  Vec3 g;
  // On the axis 1 mm above the apex: +1 mm, gradient +z; 1 mm below it: -1 mm (the dome is nearest).
  CHECK(cap->value_and_gradient(Vec3(0, 0, 1e-3), &g) == Approx(1e-3).margin(kTol));
  CHECK((g - Vec3::UnitZ()).norm() < kTol);
  CHECK(cap->value(Vec3(0, 0, -1e-3)) == Approx(-1e-3).margin(kTol));
  // Along the dome's normal at polar angle 30 deg, 2 mm out: p = c + (R + 2 mm) (sin 30, 0, cos 30), +2 mm.
  const Vec3 c(0, 0, -R), n(0.5, 0, std::sqrt(3.0) / 2);
  CHECK(cap->value_and_gradient(c + (R + 2e-3) * n, &g) == Approx(2e-3).margin(kTol));
  CHECK((g - n).norm() < 1e-9);
  // 3 mm outside the wall at mid-height (z = -7 mm): +3 mm, gradient +x; 1 mm under the bottom: +1 mm.
  CHECK(cap->value_and_gradient(Vec3(F + 3e-3, 0, -7e-3), &g) == Approx(3e-3).margin(kTol));
  CHECK((g - Vec3::UnitX()).norm() < kTol);
  CHECK(cap->value(Vec3(0, 2e-3, -T - 1e-3)) == Approx(1e-3).margin(kTol));
  // Inside, 1 mm above the bottom on the axis: the bottom is nearest (the dome is 19 mm away): -1 mm.
  CHECK(cap->value(Vec3(0, 0, -T + 1e-3)) == Approx(-1e-3).margin(kTol));
  // (1, 1) mm off the rim corner (F, -4 mm) in (r, z): the polar angle atan(13 / 17) = 37.4 deg is past the
  // rim's atan(12 / 16) = 36.9 deg, and the wall's nearest point is the corner too: sqrt 2 mm.
  CHECK(cap->value(Vec3(0, F + 1e-3, -4e-3 + 1e-3)) == Approx(std::sqrt(2.0) * 1e-3).margin(kTol));
  SECTION("the distance alone (the fast path, one point or a batch) is the distance with its gradient, everywhere") {
    // A 41^3 lattice over the cap's box grown by 5 mm: inside, outside, on the axis, beside the rim and wall.
    std::vector<Vec3> lattice;
    for (int i = 0; i <= 40; ++i)
      for (int j = 0; j <= 40; ++j)
        for (int k = 0; k <= 40; ++k)
          lattice.emplace_back(-17e-3 + 34e-3 * i / 40, -17e-3 + 34e-3 * j / 40, -15e-3 + 20e-3 * k / 40);
    std::vector<double> batch(lattice.size());
    cap->values(lattice, batch);  // the vectorised loop
    for (std::size_t i = 0; i < lattice.size(); ++i) {
      Vec3 g2;
      const double with_gradient = cap->value_and_gradient(lattice[i], &g2);
      REQUIRE(std::abs(cap->value(lattice[i]) - with_gradient) < 1e-15);
      REQUIRE(std::abs(batch[i] - with_gradient) < 1e-15);
    }
  }
  SECTION("impossible shapes are refused") {
    CHECK_THROWS_AS(make_spherical_cap_sdf(R, 25e-3, T), std::invalid_argument);  // footprint > radius
    CHECK_THROWS_AS(make_spherical_cap_sdf(R, F, 3e-3), std::invalid_argument);   // ends above the rim
  }
}

}  // namespace test_sdf_analytic
