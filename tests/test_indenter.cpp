// Procedural indenter meshes against their closed-form measures, and Poisson-disk surface sampling.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "core/base/data_root.hpp"
#include "core/geometry/indenter.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_indenter {

using namespace sb;
namespace fs = std::filesystem;

namespace {

// Flat facets inscribed in a curved surface lose area and volume of relative order (rho / R)^2, rho
// the facet circumradius, R the curvature radius.
// Icosphere, 5 subdivisions: 20480 facets of mean area 4 pi R^2 / 20480; an equilateral facet has area
// (3 sqrt 3 / 4) rho^2, so (rho / R)^2 = 4 pi / (1.299 * 20480) = 4.7e-4. Allowed: 2e-3.
constexpr double kSphereFacetTol = 2e-3;
// Torus 96 x 48 (a polygonal tube swept along a polygonal ring): perimeter factors sin(pi/n)/(pi/n)
// give area deficits (pi/48)^2/6 + (pi/96)^2/6 = 9.0e-4 (allowed 2e-3); n-gon area factors
// sin(2 pi/n)/(2 pi/n) give volume deficits (2 pi/48)^2/6 + (2 pi/96)^2/6 = 3.6e-3 (allowed 5e-3).
constexpr double kTorusAreaTol = 2e-3;
constexpr double kTorusVolumeTol = 5e-3;
// Cylinder, 96 around: the end discs are 96-gons, area factor sin(2 pi/96)/(2 pi/96) = 1 - 7.1e-4;
// fillet arcs have 6 chords per quarter (1 - (pi/24)^2/6 = 1 - 2.9e-3 on the small fillet part).
constexpr double kCylinderFacetTol = 1.5e-3;
constexpr double kExactTol = 1e-12;  // flat shapes: exact up to round-off

void check_closed_outward(const TriMesh& m, int euler) {
  const MeshReport r = validate_mesh(m);
  CHECK(r.closed());
  CHECK(r.consistently_oriented());
  CHECK(r.degenerate_faces == 0);
  CHECK(r.unreferenced_vertices == 0);
  CHECK(r.euler_characteristic == euler);
  CHECK(m.signed_volume() > 0);
  // Centred at the origin: the bounding box is symmetric.
  CHECK((m.bounds().min() + m.bounds().max()).norm() < 1e-9 * m.bounds().diagonal().norm());
}

double min_pair_distance(const std::vector<Vec3>& p) {
  double best = INFINITY;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = i + 1; j < p.size(); ++j) best = std::min(best, (p[i] - p[j]).squaredNorm());
  return std::sqrt(best);
}

double mean_nearest_neighbour(const std::vector<Vec3>& p) {
  double sum = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    double best = INFINITY;
    for (std::size_t j = 0; j < p.size(); ++j)
      if (j != i) best = std::min(best, (p[i] - p[j]).squaredNorm());
    sum += std::sqrt(best);
  }
  return sum / p.size();
}

double sum(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return s;
}

std::string data_root() {
  const char* env = std::getenv("SHEARBENCH_DATA");
  return env && *env ? std::string(env) : resolve_data_root();
}

}  // namespace

TEST_CASE("icosphere: closed, outward, area 4 pi r^2 and volume 4/3 pi r^3", "[indenter]") {
  const double r = 4e-3;
  const TriMesh m = make_sphere_mesh(r);
  CHECK(m.faces.size() == 20 * 1024);  // 20 * 4^5
  check_closed_outward(m, 2);
  CHECK(m.area() == Approx(4 * M_PI * r * r).epsilon(kSphereFacetTol));
  CHECK(m.signed_volume() == Approx(4.0 / 3 * M_PI * r * r * r).epsilon(kSphereFacetTol));
  for (const auto& v : m.vertices) CHECK(v.norm() == Approx(r).epsilon(kExactTol));
}

TEST_CASE("torus about z: closed genus 1, area 4 pi^2 R r, volume 2 pi^2 R r^2", "[indenter]") {
  const double R = 6e-3, r = 1.5e-3;
  const TriMesh m = make_torus_mesh(R, r);
  check_closed_outward(m, 0);  // genus 1: V - E + F = 0
  CHECK(m.area() == Approx(4 * M_PI * M_PI * R * r).epsilon(kTorusAreaTol));
  CHECK(m.signed_volume() == Approx(2 * M_PI * M_PI * R * r * r).epsilon(kTorusVolumeTol));
  // Extent: x in [-(R + r), R + r], z in [-r, r].
  CHECK(m.bounds().max().x() == Approx(R + r).epsilon(kExactTol));
  CHECK(m.bounds().max().z() == Approx(r).epsilon(kTorusAreaTol));
}

TEST_CASE("cylinder along z with filleted rims: Pappus' area and volume", "[indenter]") {
  SECTION("sharp edges (fillet 0): area 2 pi r^2 + 2 pi r L, volume pi r^2 L") {
    const double r = 4e-3, L = 40e-3;
    const TriMesh m = make_cylinder_mesh(r, L, 0.0);
    check_closed_outward(m, 2);
    CHECK(m.area() == Approx(2 * M_PI * r * r + 2 * M_PI * r * L).epsilon(kCylinderFacetTol));
    CHECK(m.signed_volume() == Approx(M_PI * r * r * L).epsilon(kCylinderFacetTol));
    CHECK(m.bounds().max().z() == Approx(L / 2).epsilon(kExactTol));
  }
  SECTION("fillet f (the punch r 3 mm, L 10 mm, f 0.5 mm)") {
    const double r = 3e-3, L = 10e-3, f = 0.5e-3, a = r - f;
    const TriMesh m = make_cylinder_mesh(r, L, f);
    check_closed_outward(m, 2);
    // Pappus: each quarter-circle fillet has length pi f / 2 with centroid at a + 2 f / pi from the axis,
    // so it sweeps 2 pi (a + 2f/pi)(pi f / 2) = pi^2 f a + 2 pi f^2. Two flat discs of radius a and a
    // side of height L - 2f complete the area.
    const double area = 2 * M_PI * a * a + 2 * M_PI * r * (L - 2 * f) + 2 * (M_PI * M_PI * f * a + 2 * M_PI * f * f);
    // Volume: the sharp cylinder minus, at each rim, the corner square [0,f]^2 (x = rho - a, y towards
    // the end face) less the quarter disc x^2 + y^2 <= f^2, swept around the axis:
    //   ring = 2 pi * integral (a + x) dA = 2 pi [a (1 - pi/4) f^2 + (f^3/2 - f^3/3)],
    // using integral x dA = f^3/2 over the square and f^3/3 over the quarter disc.
    const double ring = 2 * M_PI * f * f * ((1 - M_PI / 4) * a + f * (0.5 - 1.0 / 3));
    const double volume = M_PI * r * r * L - 2 * ring;
    CHECK(m.area() == Approx(area).epsilon(kCylinderFacetTol));
    CHECK(m.signed_volume() == Approx(volume).epsilon(kCylinderFacetTol));
  }
  SECTION("impossible dimensions are refused") {
    CHECK_THROWS_AS(make_cylinder_mesh(1e-3, 10e-3, 1e-3), std::invalid_argument);  // fillet = radius
    CHECK_THROWS_AS(make_cylinder_mesh(-1e-3, 10e-3, 0.0), std::invalid_argument);
  }
}

TEST_CASE("box: 12 outward triangles, exact area and volume", "[indenter]") {
  const Vec3 s(10e-3, 10e-3, 5e-3);
  const TriMesh m = make_box_mesh(s);
  CHECK(m.faces.size() == 12);
  check_closed_outward(m, 2);
  CHECK(m.area() == Approx(2 * (s.x() * s.y() + s.y() * s.z() + s.z() * s.x())).epsilon(kExactTol));
  CHECK(m.signed_volume() == Approx(s.x() * s.y() * s.z()).epsilon(kExactTol));
}

TEST_CASE("box_mesh_sdf: the exact field of a box mesh, null for anything else", "[indenter]") {
  // The TacTip import's flat surface: 80 x 80 x 10 mm, face at z_I = 0, body above (centre z = 5 mm).
  Pose X_IB = Pose::Identity();
  X_IB.translation() = Vec3(0, 0, 5e-3);
  const TriMesh m = make_box_mesh(Vec3(80e-3, 80e-3, 10e-3)).transformed(X_IB);
  const SdfPtr phi = box_mesh_sdf(m);
  REQUIRE(phi != nullptr);
  // Below the face by 2 mm: +2 mm; 1 mm inside above the face (nearest face z = 0): -1 mm; 5 mm beyond the
  // x = 40 mm side at mid-height: +5 mm; 1 mm from the corner edge (x = 40, z = 0) along both axes: sqrt 2 mm.
  CHECK(phi->value(Vec3(0, 0, -2e-3)) == Approx(2e-3).epsilon(kExactTol));
  CHECK(phi->value(Vec3(3e-3, -7e-3, 1e-3)) == Approx(-1e-3).epsilon(kExactTol));
  CHECK(phi->value(Vec3(45e-3, 0, 5e-3)) == Approx(5e-3).epsilon(kExactTol));
  CHECK(phi->value(Vec3(41e-3, 0, -1e-3)) == Approx(std::sqrt(2.0) * 1e-3).epsilon(kExactTol));

  SECTION("not a box: a sphere, four of the corners, a corner moved") {
    CHECK(box_mesh_sdf(make_sphere_mesh(5e-3, 2)) == nullptr);
    TriMesh tet;  // four corners of the unit box: all at corners, but a sixth of its volume
    tet.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
    tet.faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    CHECK(box_mesh_sdf(tet) == nullptr);
    TriMesh moved = m;
    moved.vertices[0] *= 0.9;
    CHECK(box_mesh_sdf(moved) == nullptr);
  }
  SECTION("a scene's box mesh gets it through build_indenter unless analytic_sdf is off") {
    const fs::path dir = fs::temp_directory_path() / "sb_box_mesh_sdf";
    fs::create_directories(dir);
    {
      std::ofstream f(dir / "flat.obj");
      for (const Vec3& v : m.vertices) f << "v " << v.x() << " " << v.y() << " " << v.z() << "\n";
      for (const auto& t : m.faces) f << "f " << t[0] + 1 << " " << t[1] + 1 << " " << t[2] + 1 << "\n";
    }
    IndenterSpec spec;
    spec.shape = "mesh";
    spec.mesh_path = (dir / "flat.obj").string();
    spec.sample_spacing_m = 5e-3;
    CHECK(build_indenter(spec, "", dir.string()).sdf->describe().starts_with("analytic box"));
    spec.analytic_sdf = false;
    CHECK_FALSE(build_indenter(spec, "", dir.string()).sdf->describe().starts_with("analytic box"));
    fs::remove_all(dir);
  }
}

TEST_CASE("Poisson-disk samples on a sphere: spacing, areas, outward unit normals", "[indenter]") {
  const double r = 17.5e-3, spacing = 0.75e-3;
  const TriMesh m = make_sphere_mesh(r);
  const SurfaceSamples s = poisson_disk_samples(m, spacing, 7);
  // Random sequential packing of disks of diameter `spacing` fills about 0.55 of the plane, i.e.
  // 0.55 / (pi spacing^2 / 4) = 0.70 points per spacing^2: 4 pi r^2 / spacing^2 * 0.70 = 4790 here.
  // Saturated packings range 0.5-0.75 of the plane: accept 0.60-0.95 points per spacing^2.
  const double per_spacing_sq = s.p_IS.size() * spacing * spacing / m.area();
  INFO("points " << s.p_IS.size() << ", per spacing^2 " << per_spacing_sq);
  CHECK(per_spacing_sq > 0.60);
  CHECK(per_spacing_sq < 0.95);
  REQUIRE(s.n_IS.size() == s.p_IS.size());
  REQUIRE(s.area_m2.size() == s.p_IS.size());

  // No two points closer than the spacing; so the mean nearest-neighbour distance is at least it too,
  // and a saturated packing leaves no gap of 2 spacings (mean well below 2 spacing).
  CHECK(min_pair_distance(s.p_IS) >= spacing);
  const double mean_nn = mean_nearest_neighbour(s.p_IS);
  CHECK(mean_nn >= spacing);
  CHECK(mean_nn < 1.5 * spacing);

  // Areas sum to the mesh area (within 2 %), each positive.
  constexpr double kAreaSumTol = 0.02;
  CHECK(sum(s.area_m2) == Approx(m.area()).epsilon(kAreaSumTol));
  for (double a : s.area_m2) CHECK(a > 0);

  // On the surface (between the facets' inscribed depth and r) with unit outward normals.
  constexpr double kUnitTol = 1e-12;
  constexpr double kRadialAlignment = 0.99;
  int off_surface = 0, bad_normal = 0;
  for (std::size_t i = 0; i < s.p_IS.size(); ++i) {
    if (s.p_IS[i].norm() > r * (1 + kUnitTol) || s.p_IS[i].norm() < r * (1 - kSphereFacetTol)) ++off_surface;
    if (std::abs(s.n_IS[i].norm() - 1) > kUnitTol || s.n_IS[i].dot(s.p_IS[i].normalized()) < kRadialAlignment)
      ++bad_normal;
  }
  CHECK(off_surface == 0);
  CHECK(bad_normal == 0);
}

TEST_CASE("Poisson-disk sampling is deterministic for a seed", "[indenter]") {
  const TriMesh m = make_torus_mesh(6e-3, 1.5e-3);
  const SurfaceSamples a = poisson_disk_samples(m, 0.75e-3, 3);
  const SurfaceSamples b = poisson_disk_samples(m, 0.75e-3, 3);
  const SurfaceSamples c = poisson_disk_samples(m, 0.75e-3, 4);
  REQUIRE(a.p_IS.size() == b.p_IS.size());
  CHECK(a.p_IS == b.p_IS);
  CHECK(a.area_m2 == b.area_m2);
  CHECK(a.p_IS != c.p_IS);
  // Box: flat faces give exact face normals, axis-aligned.
  const SurfaceSamples box = poisson_disk_samples(make_box_mesh(Vec3(10e-3, 10e-3, 5e-3)), 0.75e-3);
  for (const auto& n : box.n_IS) CHECK(n.cwiseAbs().maxCoeff() == Approx(1.0).epsilon(kExactTol));
}

TEST_CASE("sampling the cow at 6 cm, 0.75 mm spacing covers its area evenly", "[indenter][data]") {
  const std::string path = (fs::path(data_root()) / "meshes/cow.obj").string();
  if (!fs::exists(path)) FAIL("test data missing: " << path << " (set SHEARBENCH_DATA)");
  // SOURCE.md: about 10.4 units long; 0.06 / 10.4 m per unit makes it 6 cm.
  MeshLoadOptions opt;
  opt.scale = 0.06 / 10.4;
  const TriMesh cow = load_mesh(path, opt);
  // Its speed is a benchmark (bench/bench_sampling.cpp, BM_PoissonDiskCow), not a timed test.
  const SurfaceSamples s = poisson_disk_samples(cow, 0.75e-3);
  INFO(s.p_IS.size() << " points");
  CHECK(sum(s.area_m2) == Approx(cow.area()).epsilon(0.02));
  // Saturated packing, as on the sphere: 0.60-0.95 points per spacing^2 of area.
  const double per_spacing_sq = s.p_IS.size() * 0.75e-3 * 0.75e-3 / cow.area();
  CHECK(per_spacing_sq > 0.60);
  CHECK(per_spacing_sq < 0.95);
}

TEST_CASE("indenter shapes from specs: procedural, loaded, analytic fields", "[indenter]") {
  IndenterSpec sphere;
  sphere.shape = "sphere";
  sphere.radius_m = 4e-3;
  const TriMesh m = make_indenter_mesh(sphere, "", "");
  CHECK(m.bounds().max().x() == Approx(4e-3).epsilon(kExactTol));
  const SdfPtr phi = make_analytic_indenter_sdf(sphere);
  REQUIRE(phi);
  CHECK(phi->value(Vec3(6e-3, 0, 0)) == Approx(2e-3).epsilon(kExactTol));  // 6 mm from the centre, r 4 mm

  IndenterSpec peg;
  peg.shape = "cylinder";
  peg.fillet_m = 0.5e-3;
  CHECK_FALSE(make_analytic_indenter_sdf(peg));  // filleted: no exact field, the mesh SDF is used
  peg.fillet_m = 0;
  CHECK(make_analytic_indenter_sdf(peg));

  IndenterSpec bad;
  bad.shape = "pyramid";
  CHECK_THROWS_AS(make_indenter_mesh(bad, "", ""), InputError);
  bad.shape = "torus";
  bad.radius_m = 1e-3;
  bad.minor_radius_m = 2e-3;  // tube thicker than the ring
  CHECK_THROWS_AS(make_indenter_mesh(bad, "", ""), InputError);

  IndenterSpec file;
  file.shape = "mesh";
  file.mesh_path = "data:meshes/spot.obj";
  file.scale = 0.01;
  if (!fs::exists(fs::path(data_root()) / "meshes/spot.obj")) FAIL("test data missing: spot.obj under " << data_root());
  const TriMesh spot = make_indenter_mesh(file, data_root(), "");
  // SOURCE.md: spot's box is about 0.94 x 1.69 x 1.72 units: 17.2 mm at 0.01 m per unit.
  CHECK(spot.bounds().sizes().maxCoeff() == Approx(0.0172).epsilon(0.01));
  file.mesh_path = "data:meshes/missing.obj";
  CHECK_THROWS_AS(make_indenter_mesh(file, data_root(), ""), InputError);
}

TEST_CASE("the committed assets/ meshes load clean and match their generators", "[indenter][mesh]") {
  // Written by `shearbench assets`; regenerate them if a generator changes.
  const fs::path dir = fs::path(SHEARBENCH_SOURCE_DIR) / "assets";
  struct Expected {
    const char* file;
    TriMesh mesh;
  };
  const Expected assets[] = {{"sphere_r4.obj", make_sphere_mesh(4e-3)},
                             {"torus_R6_r1.5.obj", make_torus_mesh(6e-3, 1.5e-3)},
                             {"cylinder_r4_l40_f0.5.obj", make_cylinder_mesh(4e-3, 40e-3, 0.5e-3)},
                             {"punch_r3_f0.5.obj", make_cylinder_mesh(3e-3, 10e-3, 0.5e-3)},
                             {"box_10x10x5.obj", make_box_mesh(Vec3(10e-3, 10e-3, 5e-3))}};
  // Written with 9 digits and read as 32-bit floats: relative 6e-8 on the volume, allowed 1e-6.
  constexpr double kFileTol = 1e-6;
  for (const auto& a : assets) {
    INFO(a.file);
    Warnings w;
    const TriMesh m = load_mesh((dir / a.file).string(), {}, nullptr, &w);
    CHECK(w.empty());
    CHECK(m.faces.size() == a.mesh.faces.size());
    CHECK(m.signed_volume() == Approx(a.mesh.signed_volume()).epsilon(kFileTol));
  }
}

}  // namespace test_indenter
