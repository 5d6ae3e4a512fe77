// Dense grid cache of an SDF: trilinear (exact for linear fields) and nearest-node (pytorch_volumetric
// CachedSDF) lookups, node layout, and the out-of-range fallback to the source.
#include <catch2/catch.hpp>

#include <cmath>

#include "core/geometry/sdf.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_sdf_grid {

using sb::Vec3;

namespace {
// Values are stored as float: a few millimetres carry a rounding error of ~1e-10 m.
constexpr double kFloatStorage = 1e-9;
constexpr double mm = 1e-3;
}  // namespace

TEST_CASE("grid SDF: node layout follows pytorch_volumetric (round(extent / voxel) + 1 nodes)", "[sdf]") {
  // Region z from -0.3 mm to 4.1 mm, voxel 1 mm: round(4.4) = 4 cells, 5 nodes at -0.3, 0.7, ..., 3.7 mm;
  // the box's max side moves to -0.3 + 4 = 3.7 mm.
  const Eigen::AlignedBox3d region(Vec3(0, 0, -0.3) * mm, Vec3(4, 4, 4.1) * mm);
  const auto grid = sb::make_grid_sdf(sb::make_halfspace_sdf(), region, 1 * mm, sb::GridLookup::kNearest);
  CHECK(grid->bounds().min().z() == Approx(-0.3 * mm).margin(1e-15));
  CHECK(grid->bounds().max().z() == Approx(3.7 * mm).margin(1e-15));
  CHECK(grid->bounds().max().x() == Approx(4 * mm).margin(1e-15));
}

TEST_CASE("grid SDF trilinear lookup reproduces a half-space exactly", "[sdf]") {
  // phi = z is linear, and trilinear interpolation of a linear function is the function itself.
  const Eigen::AlignedBox3d region(Vec3(0, 0, -0.3) * mm, Vec3(4, 4, 4.1) * mm);
  const auto grid = sb::make_grid_sdf(sb::make_halfspace_sdf(), region, 1 * mm, sb::GridLookup::kTrilinear);
  for (const Vec3& p : {Vec3(1.3, 2.7, 2.45), Vec3(0.01, 3.99, -0.29), Vec3(3.5, 0.5, 3.7), Vec3(2, 2, 0.7)}) {
    Vec3 g;
    const double v = grid->value_and_gradient(p * mm, &g);
    CHECK(v == Approx(p.z() * mm).margin(kFloatStorage));
    CHECK(grid->value(p * mm) == v);
    CHECK(g.isApprox(Vec3::UnitZ(), 1e-6));
  }
}

TEST_CASE("grid SDF nearest lookup returns the value at the rounded node", "[sdf]") {
  // Nodes at z = -0.3 + k mm. Query z = 2.45 mm: (2.45 + 0.3) / 1 = 2.75 rounds to k = 3, node z = 2.7 mm.
  // Query z = 2.15 mm: 2.45 rounds to k = 2, node z = 1.7 mm. x and y do not matter for phi = z.
  const Eigen::AlignedBox3d region(Vec3(0, 0, -0.3) * mm, Vec3(4, 4, 4.1) * mm);
  const auto grid = sb::make_grid_sdf(sb::make_halfspace_sdf(), region, 1 * mm, sb::GridLookup::kNearest);
  Vec3 g;
  CHECK(grid->value_and_gradient(Vec3(1.3, 2.7, 2.45) * mm, &g) == Approx(2.7 * mm).margin(kFloatStorage));
  CHECK(g == Vec3::UnitZ());
  CHECK(grid->value(Vec3(1.3, 2.7, 2.15) * mm) == Approx(1.7 * mm).margin(kFloatStorage));
  // Piecewise constant: every point whose z rounds to the same node gives the same value.
  CHECK(grid->value(Vec3(0.2, 0.2, 2.21) * mm) == grid->value(Vec3(3.8, 3.1, 3.19) * mm));
}

TEST_CASE("grid SDF out of range falls back to the source field", "[sdf]") {
  // The covered box is z in [-0.3, 3.7] mm. Nearest: z = 4.1 mm gives index (4.1 + 0.3) = 4.4 -> 4, still the
  // last node (3.7 mm); z = 4.3 mm gives 4.6 -> 5, outside: the source answers exactly, 4.3 mm.
  const Eigen::AlignedBox3d region(Vec3(0, 0, -0.3) * mm, Vec3(4, 4, 4.1) * mm);
  const auto nearest = sb::make_grid_sdf(sb::make_halfspace_sdf(), region, 1 * mm, sb::GridLookup::kNearest);
  CHECK(nearest->value(Vec3(1, 1, 4.1) * mm) == Approx(3.7 * mm).margin(kFloatStorage));
  CHECK(nearest->value(Vec3(1, 1, 4.3) * mm) == 4.3 * mm);
  CHECK(nearest->value(Vec3(-7, 1, 1) * mm) == 1 * mm);
  // Trilinear: anything outside the box goes to the source.
  const auto tri = sb::make_grid_sdf(sb::make_halfspace_sdf(), region, 1 * mm, sb::GridLookup::kTrilinear);
  CHECK(tri->value(Vec3(1, 1, 25) * mm) == 25 * mm);
}

TEST_CASE("grid SDF trilinear error on a sphere is within the curvature bound", "[sdf]") {
  // phi = |p| - R has Hessian eigenvalues (0, 1/|p|, 1/|p|); the trilinear interpolation error is at most
  // sum_d h^2/8 * |d2phi/dx_d2| <= 3 h^2 / (8 |p|). With h = 0.1 mm and |p| >= 2 mm: 1.9e-3 mm.
  constexpr double R = 4 * mm, h = 0.1 * mm, rho_min = 2 * mm;
  const double kCurvatureBound = 3 * h * h / (8 * rho_min) + kFloatStorage;
  const auto sphere = sb::make_sphere_sdf(R);
  const Eigen::AlignedBox3d region(Vec3::Constant(-6 * mm), Vec3::Constant(6 * mm));
  const auto grid = sb::make_grid_sdf(sphere, region, h, sb::GridLookup::kTrilinear);
  double worst = 0;
  for (int i = 0; i < 500; ++i) {
    // A deterministic spiral of directions at radii from 2 to 6 mm.
    const double t = (i + 0.5) / 500, z = 1 - 2 * t, s = std::sqrt(1 - z * z), a = i * 2.399963;
    const Vec3 p = (rho_min + 3.9 * mm * t) * Vec3(s * std::cos(a), s * std::sin(a), z);
    Vec3 g;
    const double v = grid->value_and_gradient(p, &g);
    worst = std::max(worst, std::abs(v - sphere->value(p)));
    CHECK(v == Approx(sphere->value(p)).margin(kCurvatureBound));
    CHECK(g.dot(p.normalized()) > std::cos(2.0 * M_PI / 180));
  }
  WARN("grid trilinear worst error " << worst / mm << " mm (bound " << kCurvatureBound / mm << " mm)");
}

}  // namespace test_sdf_grid
