// Mesh SDF (OpenVDB narrow band): accuracy against the exact distance to the same triangle mesh, gradient
// direction, band clamping, bounds, batch/concurrent consistency, and robustness on cow.obj.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <thread>

#include "core/base/data_root.hpp"
#include "core/geometry/indenter.hpp"
#include "core/geometry/mesh.hpp"
#include "core/geometry/sdf.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_sdf {

namespace {

using sb::Vec3;

// Unsigned distance from p to the mesh, brute force over every triangle.
double mesh_distance(const sb::TriMesh& m, const Vec3& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& f : m.faces)
    best = std::min(best, sb::point_triangle_distance(p, m.vertices[f[0]], m.vertices[f[1]], m.vertices[f[2]]));
  return best;
}

// Inside test by ray parity along a generic (irrational-ish) direction, Moller-Trumbore per triangle.
bool inside_by_parity(const sb::TriMesh& m, const Vec3& p) {
  const Vec3 dir = Vec3(0.5773, 0.3123, 0.7547).normalized();
  int crossings = 0;
  for (const auto& f : m.faces) {
    const Vec3 &a = m.vertices[f[0]], &b = m.vertices[f[1]], &c = m.vertices[f[2]];
    const Vec3 e1 = b - a, e2 = c - a, h = dir.cross(e2);
    const double det = e1.dot(h);
    if (std::abs(det) < 1e-18) continue;
    const Vec3 s = p - a;
    const double u = s.dot(h) / det;
    if (u < 0 || u > 1) continue;
    const Vec3 q = s.cross(e1);
    const double v = dir.dot(q) / det;
    if (v < 0 || u + v > 1) continue;
    if (e2.dot(q) / det > 0) ++crossings;
  }
  return crossings % 2 == 1;
}

double angle_deg(const Vec3& a, const Vec3& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / M_PI;
}

// Probe points p = surface point + depth * outward normal of the ideal shape, depths in [-3 mm, +3 mm]
// (clipped to `max_inside` for thin shapes).
struct Probe {
  Vec3 p;
  Vec3 normal;
};

std::string data_root() {
  const char* env = std::getenv("SHEARBENCH_DATA");
  return env ? std::string(env) : sb::resolve_data_root();
}

}  // namespace

TEST_CASE("mesh SDF of an icosphere matches the exact distance to the same mesh", "[sdf][slow]") {
  // Sphere r = 5 mm, icosphere level 5 (10,242 vertices); default voxel = min(diag/200, 0.25 mm) where the
  // bbox diagonal is sqrt(3) * 10 mm, so voxel = 0.0866 mm. Band 4 mm.
  constexpr double r = 0.005;
  const sb::TriMesh mesh = sb::make_sphere_mesh(r, 5);
  const auto sdf = sb::make_mesh_sdf(mesh);
  const double voxel = std::sqrt(3.0) * 2 * r / 200;
  // The requirement: within 2 % of a voxel of the exact (brute-force) signed distance to the mesh.
  const double kValueTolerance = 0.02 * voxel;
  // Faceting: facet normals differ from the sphere's by about half the edge angle (~1 deg at level 5).
  constexpr double kAngleToleranceDeg = 3.0;

  std::mt19937 rng(7);
  std::uniform_real_distribution<double> depth(-0.003, 0.003);
  std::normal_distribution<double> gauss;
  double worst = 0, worst_angle = 0;
  for (int i = 0; i < 300; ++i) {
    const Vec3 n = Vec3(gauss(rng), gauss(rng), gauss(rng)).normalized();
    double d = depth(rng);
    if (std::abs(d) < 1e-5) d = 1e-5;  // stay clear of the sagitta (< 1 um) so the sign is unambiguous
    const Vec3 p = (r + d) * n;
    const double exact = (d < 0 ? -1.0 : 1.0) * mesh_distance(mesh, p);
    Vec3 g;
    const double v = sdf->value_and_gradient(p, &g);
    worst = std::max(worst, std::abs(v - exact));
    worst_angle = std::max(worst_angle, angle_deg(g, n));
    CHECK(v == Approx(exact).margin(kValueTolerance));
    CHECK(angle_deg(g, n) < kAngleToleranceDeg);
  }
  WARN("icosphere: worst |phi - exact| = " << worst / voxel << " voxel, worst normal angle " << worst_angle << " deg ("
                                           << sdf->describe() << ")");
}

TEST_CASE("mesh SDF of a torus matches the exact distance to the same mesh", "[sdf][slow]") {
  // Torus R = 6 mm, r = 2 mm, 256 x 128 facets. Probes from 1.5 mm inside (the tube centre is at 2 mm depth)
  // to 3 mm outside.
  constexpr double R = 0.006, r = 0.002;
  const sb::TriMesh mesh = sb::make_torus_mesh(R, r, 256, 128);
  const auto sdf = sb::make_mesh_sdf(mesh);
  const auto analytic = sb::make_torus_sdf(R, r);
  // bbox 16 x 16 x 4 mm: diagonal sqrt(16^2 + 16^2 + 4^2) = 23 mm, /200 = 0.115 mm < 0.25 mm.
  const double h = std::sqrt(16.0 * 16 + 16 * 16 + 4 * 4) * 1e-3 / 200;
  // Trilinear interpolation of the exact field phi errs by up to h^2/8 * sum|d2phi/dx_d^2|. Two terms are
  // not OpenVDB's but the field's own: (1) curvature, 1/rho where rho = r + d is the distance to the tube's
  // centre circle (the ridge of phi), so h^2 / (8 rho); (2) inside a faceted mesh, phi has creases on the
  // bisector planes of adjacent facets, a gradient jump of about the facet angle theta = 2 pi / 128: an error
  // of up to h * theta / 4. The requirement (2 % of a voxel) applies on top of both.
  const double theta = 2 * M_PI / 128;
  // Gradient: the trilinear interpolant's gradient errs by about h * |Hessian| / 2 = h / (2 rho) rad, on top
  // of the facet-vs-tube normal difference (<= theta / 2 = 1.4 deg): 3 deg plus the curvature term.
  constexpr double kAngleToleranceDeg = 3.0;

  std::mt19937 rng(11);
  std::uniform_real_distribution<double> angle(0, 2 * M_PI), depth(-0.0015, 0.003);
  double worst = 0, worst_angle = 0;
  for (int i = 0; i < 300; ++i) {
    const double u = angle(rng), w = angle(rng);
    double d = depth(rng);
    if (std::abs(d) < 2e-5) d = 2e-5;  // sagitta of 256 x 128 facets is ~1 um
    const Vec3 radial(std::cos(u), std::sin(u), 0);
    const Vec3 n = std::cos(w) * radial + std::sin(w) * Vec3::UnitZ();
    const Vec3 p = R * radial + (r + d) * n;
    const double exact = (d < 0 ? -1.0 : 1.0) * mesh_distance(mesh, p);
    const double interpolation = h * h / (8 * (r + d)) + (d < 0 ? h * theta / 4 : 0.0);
    const double tolerance = 0.02 * h + interpolation;
    Vec3 g, g_analytic;
    const double v = sdf->value_and_gradient(p, &g);
    analytic->value_and_gradient(p, &g_analytic);
    worst = std::max(worst, std::abs(v - exact) - interpolation);
    worst_angle = std::max(worst_angle, angle_deg(g, g_analytic));
    CHECK(v == Approx(exact).margin(tolerance));
    CHECK(angle_deg(g, g_analytic) < kAngleToleranceDeg + h / (2 * (r + d)) * 180 / M_PI);
  }
  WARN("torus: worst |phi - exact| beyond the interpolation bound = " << worst / h << " voxel, worst normal angle "
                                                                      << worst_angle << " deg");
}

TEST_CASE("mesh SDF is exact at voxel centres", "[sdf][slow]") {
  // With p on a voxel centre (p = voxel * integer) trilinear interpolation returns the stored value alone:
  // this isolates OpenVDB's distance computation from interpolation. Stored as float: ~1e-7 relative.
  constexpr double r = 0.005, voxel = 0.0001;
  const sb::TriMesh mesh = sb::make_sphere_mesh(r, 4);
  sb::MeshSdfOptions options;
  options.voxel_size = voxel;
  const auto sdf = sb::make_mesh_sdf(mesh, options);
  const auto sphere = sb::make_sphere_sdf(r);
  constexpr double kFloatStorage = 1e-9;  // metres
  std::mt19937 rng(2);
  std::uniform_int_distribution<int> idx(-80, 80);
  int probed = 0;
  double worst = 0;
  while (probed < 200) {
    const Vec3 p = voxel * Vec3(idx(rng), idx(rng), idx(rng));
    const double ideal = sphere->value(p);
    if (std::abs(ideal) > 0.003 || std::abs(ideal) < 1e-5) continue;
    ++probed;
    const double exact = (ideal < 0 ? -1.0 : 1.0) * mesh_distance(mesh, p);
    worst = std::max(worst, std::abs(sdf->value(p) - exact));
    CHECK(sdf->value(p) == Approx(exact).margin(kFloatStorage));
  }
  WARN("voxel centres: worst |phi - exact| = " << worst / voxel << " voxel");
}

TEST_CASE("mesh SDF clamps to the band outside it and reports the grown bounds", "[sdf]") {
  constexpr double r = 0.005;
  const sb::TriMesh mesh = sb::make_sphere_mesh(r, 3);
  sb::MeshSdfOptions options;
  options.band_width = 0.003;
  options.voxel_size = 0.0002;
  const auto sdf = sb::make_mesh_sdf(mesh, options);
  // 10 mm beyond the surface and the centre (5 mm deep) are both past the 3 mm band: +-band exactly.
  CHECK(sdf->value(Vec3(0, 0, r + 0.010)) == options.band_width);
  CHECK(sdf->value(Vec3::Zero()) == -options.band_width);
  // Far outside the gradient still points away from the mesh (the bbox-centre fallback).
  Vec3 g;
  sdf->value_and_gradient(Vec3(0, 0, 0.05), &g);
  CHECK(g.z() == Approx(1.0));
  // bounds = mesh bbox [-r, r]^3 (icosphere vertices reach +-r on the axes) grown by the band.
  const auto b = sdf->bounds();
  constexpr double kBoundsTolerance = 1e-12;
  CHECK(b.min().x() == Approx(-r - options.band_width).margin(kBoundsTolerance));
  CHECK(b.max().z() == Approx(r + options.band_width).margin(kBoundsTolerance));
}

TEST_CASE("mesh SDF batch and concurrent queries agree with single queries", "[sdf][slow]") {
  const sb::TriMesh mesh = sb::make_sphere_mesh(0.004, 4);
  const auto sdf = sb::make_mesh_sdf(mesh);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.007, 0.007);
  std::vector<Vec3> p(20000);
  for (auto& q : p) q = Vec3(u(rng), u(rng), u(rng));
  std::vector<double> single(p.size()), batch(p.size()), threaded(p.size()), batch_g(p.size());
  std::vector<Vec3> grads(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) single[i] = sdf->value(p[i]);
  sdf->values(p, batch);
  sdf->values_and_gradients(p, batch_g, grads);
  // Two threads each answer half of the batch at the same time.
  const std::size_t half = p.size() / 2;
  std::thread t1([&] { sdf->values(std::span(p).first(half), std::span(threaded).first(half)); });
  std::thread t2([&] { sdf->values(std::span(p).subspan(half), std::span(threaded).subspan(half)); });
  t1.join();
  t2.join();
  CHECK(batch == single);
  CHECK(batch_g == single);
  CHECK(threaded == single);
}

TEST_CASE("mesh SDF of cow.obj (closed, not a clean manifold) has the right sign", "[sdf]") {
  const std::string path = data_root() + "/meshes/cow.obj";
  INFO("needs " << path);
  REQUIRE(std::filesystem::exists(path));
  sb::MeshLoadOptions load;
  load.scale = 0.005;  // about 10.4 units long: 5.2 cm
  const sb::TriMesh cow = sb::load_mesh(path, load);
  const auto sdf = sb::make_mesh_sdf(cow);
  const auto box = cow.bounds();
  const double voxel = std::min(box.diagonal().norm() / 200, 0.25e-3);
  // Probes closer than a few voxels to the surface are skipped: there the sign is a matter of interpolation.
  const double kClearance = 3 * voxel;
  std::mt19937 rng(5);
  int inside = 0, outside = 0;
  for (int i = 0; i < 400; ++i) {
    Vec3 p;
    for (int d = 0; d < 3; ++d) p[d] = std::uniform_real_distribution<double>(box.min()[d], box.max()[d])(rng);
    const double dist = mesh_distance(cow, p);
    if (dist < kClearance) continue;
    const bool in = inside_by_parity(cow, p);
    (in ? inside : outside)++;
    const double v = sdf->value(p);
    INFO("probe " << p.transpose() << " distance " << dist << " inside " << in << " phi " << v);
    CHECK((in ? v < 0 : v > 0));
    // cow.obj is coarse (5,804 triangles): inside, its distance field has creases with gradient jumps of tens
    // of degrees, which trilinear interpolation rounds off by up to ~h * jump / 4: allow a fifth of a voxel.
    const double kCoarseMeshTolerance = 0.2 * voxel;
    if (dist < 0.003) CHECK(std::abs(v) == Approx(dist).margin(kCoarseMeshTolerance));
  }
  CHECK(inside > 20);
  CHECK(outside > 20);
}

TEST_CASE("mesh SDF of an open mesh (allow_open) keeps a best-effort sign", "[sdf][slow]") {
  // An icosphere with one triangle removed: a hole of about one edge (0.17 mm) at level 5, r = 5 mm.
  constexpr double r = 0.005;
  sb::TriMesh mesh = sb::make_sphere_mesh(r, 5);
  mesh.faces.erase(mesh.faces.begin());
  sb::MeshSdfOptions options;
  options.allow_open = true;
  const auto sdf = sb::make_mesh_sdf(mesh, options);
  CHECK(sdf->value(Vec3(0, 0, 0.002)) < 0);  // 3 mm deep
  CHECK(sdf->value(Vec3(0, 0.006, 0)) > 0);  // 1 mm outside
  CHECK(sdf->value(Vec3(0.004, 0, 0)) == Approx(-0.001).margin(1e-5));
}

TEST_CASE("point_triangle_distance in each closest-point region", "[sdf]") {
  // Triangle a = (0,0,0), b = (1,0,0), c = (0,1,0) in the plane z = 0.
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  constexpr double kTol = 1e-12;
  // Above the face: the distance is the height.
  CHECK(sb::point_triangle_distance(Vec3(0.25, 0.25, 2), a, b, c) == Approx(2).margin(kTol));
  // Beyond vertex a in -x, -y: |(-1, -1, 0)| = sqrt(2).
  CHECK(sb::point_triangle_distance(Vec3(-1, -1, 0), a, b, c) == Approx(std::sqrt(2.0)).margin(kTol));
  // Below edge ab (y < 0, 0 < x < 1): the distance is |y| = 1.
  CHECK(sb::point_triangle_distance(Vec3(0.5, -1, 0), a, b, c) == Approx(1).margin(kTol));
  // Beyond edge bc (x + y = 1): |1 + 1 - 1| / sqrt(2) from (1, 1, 0).
  CHECK(sb::point_triangle_distance(Vec3(1, 1, 0), a, b, c) == Approx(1 / std::sqrt(2.0)).margin(kTol));
  // Beyond vertex c along +y and above: |(0, 1, 1)| = sqrt(2).
  CHECK(sb::point_triangle_distance(Vec3(0, 2, 1), a, b, c) == Approx(std::sqrt(2.0)).margin(kTol));
}

}  // namespace test_sdf
