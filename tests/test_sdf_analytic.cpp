#include <catch2/catch.hpp>
#include <cmath>

#include "core/geometry/sdf.hpp"

using namespace sb;

namespace {
constexpr double kExact = 1e-12;  // metres: closed-form distances
}

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
