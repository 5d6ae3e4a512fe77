// Mesh loading (every format, every bad input), validation and measures. Fixture meshes are written by
// the tests themselves into a temporary directory.
#include <unistd.h>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "core/base/data_root.hpp"
#include "core/geometry/mesh.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_mesh {

using namespace sb;
namespace fs = std::filesystem;

namespace {

// Text formats round numbers like 0, 1 exactly; measures of O(1) meshes are exact up to round-off.
constexpr double kExactTol = 1e-12;

// The unit tetrahedron (0,0,0), (1,0,0), (0,1,0), (0,0,1), faces wound outward:
//   area  = three right triangles of 1/2 + one equilateral triangle of side sqrt(2), (sqrt(3)/4) * 2
//         = 3/2 + sqrt(3)/2;   volume = 1/6.
const double kTetArea = 1.5 + std::sqrt(3.0) / 2;
const double kTetVolume = 1.0 / 6;
const char* kTetVertices[] = {"0 0 0", "1 0 0", "0 1 0", "0 0 1"};
const int kTetFaces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};

// The unit cube [0,1]^3 with six quads (OBJ and OFF may hold polygons; they are triangulated):
//   area 6, volume 1, 12 triangles.
const char* kCubeVertices[] = {"0 0 0", "1 0 0", "0 1 0", "1 1 0", "0 0 1", "1 0 1", "0 1 1", "1 1 1"};
const int kCubeQuads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};

fs::path temp_dir() {
  static const fs::path dir = [] {
    fs::path d = fs::temp_directory_path() / ("sb_test_mesh_" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
  }();
  return dir;
}

fs::path write_text(const std::string& name, const std::string& text) {
  const fs::path p = temp_dir() / name;
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

std::string tet_obj(bool inward = false, int drop_face = -1) {
  std::ostringstream s;
  for (auto v : kTetVertices) s << "v " << v << "\n";
  for (int f = 0; f < 4; ++f) {
    if (f == drop_face) continue;
    const int* t = kTetFaces[f];
    if (inward)
      s << "f " << t[0] + 1 << " " << t[2] + 1 << " " << t[1] + 1 << "\n";
    else
      s << "f " << t[0] + 1 << " " << t[1] + 1 << " " << t[2] + 1 << "\n";
  }
  return s.str();
}

std::string cube_obj() {
  std::ostringstream s;
  s << "# unit cube\n";
  for (auto v : kCubeVertices) s << "v " << v << "\n";
  for (const auto& q : kCubeQuads)
    s << "f " << q[0] + 1 << " " << q[1] + 1 << " " << q[2] + 1 << " " << q[3] + 1 << "\n";
  return s.str();
}

std::string cube_off() {
  std::ostringstream s;
  s << "OFF\n8 6 12\n";
  for (auto v : kCubeVertices) s << v << "\n";
  for (const auto& q : kCubeQuads) s << "4 " << q[0] << " " << q[1] << " " << q[2] << " " << q[3] << "\n";
  return s.str();
}

Vec3 tet_vertex(int i) {
  std::istringstream s(kTetVertices[i]);
  Vec3 v;
  s >> v.x() >> v.y() >> v.z();
  return v;
}

std::string tet_ascii_stl() {
  std::ostringstream s;
  s << "solid tet\n";
  for (const auto& t : kTetFaces) {
    s << " facet normal 0 0 0\n  outer loop\n";
    for (int k = 0; k < 3; ++k) s << "   vertex " << kTetVertices[t[k]] << "\n";
    s << "  endloop\n endfacet\n";
  }
  s << "endsolid tet\n";
  return s.str();
}

std::string tet_binary_stl(float poison = 0.0f) {
  std::string out(80, ' ');
  const std::uint32_t n = 4;
  out.append(reinterpret_cast<const char*>(&n), 4);
  for (const auto& t : kTetFaces) {
    float rec[12] = {0, 0, 0};  // normal, then three vertices
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) rec[3 + 3 * k + c] = static_cast<float>(tet_vertex(t[k])[c]);
    if (&t == &kTetFaces[3]) rec[11] += poison;  // last coordinate of the last triangle
    out.append(reinterpret_cast<const char*>(rec), sizeof rec);
    out.append(2, '\0');  // attribute byte count
  }
  return out;
}

std::string tet_ply() {
  std::ostringstream s;
  s << "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
       "element face 4\nproperty list uchar int vertex_indices\nend_header\n";
  for (auto v : kTetVertices) s << v << "\n";
  for (const auto& t : kTetFaces) s << "3 " << t[0] << " " << t[1] << " " << t[2] << "\n";
  return s.str();
}

std::string tet_binary_ply() {
  std::string out =
      "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n";
  for (int i = 0; i < 4; ++i) {
    const float v[3] = {float(tet_vertex(i).x()), float(tet_vertex(i).y()), float(tet_vertex(i).z())};
    out.append(reinterpret_cast<const char*>(v), sizeof v);
  }
  for (const auto& t : kTetFaces) {
    out.push_back('\3');
    out.append(reinterpret_cast<const char*>(t), 3 * sizeof(int));
  }
  return out;
}

void check_tetrahedron(const TriMesh& m, double scale) {
  CHECK(m.vertices.size() == 4);
  CHECK(m.faces.size() == 4);
  CHECK(m.area() == Approx(kTetArea * scale * scale).epsilon(kExactTol));
  CHECK(m.signed_volume() == Approx(kTetVolume * scale * scale * scale).epsilon(kExactTol));
}

std::string data_root() {
  const char* env = std::getenv("SHEARBENCH_DATA");
  return env && *env ? std::string(env) : resolve_data_root();
}

std::string require_data(const std::string& relative) {
  const std::string p = (fs::path(data_root()) / relative).string();
  if (!fs::exists(p)) FAIL("test data missing: " << p << " (set SHEARBENCH_DATA)");
  return p;
}

bool mentions(const Warnings& w, const std::string& what) {
  for (const auto& m : w.messages)
    if (m.find(what) != std::string::npos) return true;
  return false;
}

}  // namespace

TEST_CASE("every mesh format loads the same solid, scaled to metres", "[mesh]") {
  // Each fixture is in millimetres; scale 1e-3 gives metres, so area scales by 1e-6 and volume by 1e-9.
  constexpr double kMm = 1e-3;
  MeshLoadOptions mm;
  mm.scale = kMm;
  SECTION("OBJ with quads, triangulated") {
    Warnings w;
    MeshReport r;
    const TriMesh m = load_mesh(write_text("cube.obj", cube_obj()).string(), mm, &r, &w);
    CHECK(m.vertices.size() == 8);
    CHECK(m.faces.size() == 12);
    CHECK(m.area() == Approx(6 * kMm * kMm).epsilon(kExactTol));
    CHECK(m.signed_volume() == Approx(1 * kMm * kMm * kMm).epsilon(kExactTol));
    CHECK(r.closed());
    CHECK(r.consistently_oriented());
    CHECK(r.euler_characteristic == 2);  // genus 0: V - E + F = 8 - 18 + 12
    CHECK(w.empty());
  }
  SECTION("OFF with quads") {
    const TriMesh m = load_mesh(write_text("cube.off", cube_off()).string(), mm);
    CHECK(m.faces.size() == 12);
    CHECK(m.signed_volume() == Approx(1 * kMm * kMm * kMm).epsilon(kExactTol));
  }
  SECTION("ASCII STL (vertices merged by position)") {
    MeshReport r;
    check_tetrahedron(load_mesh(write_text("tet_ascii.stl", tet_ascii_stl()).string(), mm, &r), kMm);
    CHECK(r.closed());
  }
  SECTION("binary STL") {
    MeshReport r;
    check_tetrahedron(load_mesh(write_text("tet_binary.stl", tet_binary_stl()).string(), mm, &r), kMm);
    CHECK(r.closed());
  }
  SECTION("binary PLY") { check_tetrahedron(load_mesh(write_text("tet_bin.ply", tet_binary_ply()).string(), mm), kMm); }
  SECTION("PLY") { check_tetrahedron(load_mesh(write_text("tet.ply", tet_ply()).string(), mm), kMm); }
  SECTION("upper-case extension") { check_tetrahedron(load_mesh(write_text("TET.OBJ", tet_obj()).string(), mm), kMm); }
}

TEST_CASE("bad mesh files are rejected with an error naming the file", "[mesh]") {
  const MeshLoadOptions opt;
  auto expect_error = [](const fs::path& p, const std::string& fragment) {
    try {
      load_mesh(p.string(), MeshLoadOptions{});
      FAIL("no error for " << p);
    } catch (const InputError& e) {
      CHECK(e.file() == p.string());
      INFO(e.what());
      CHECK(std::string(e.what()).find(fragment) != std::string::npos);
    }
  };
  SECTION("missing file") { expect_error(temp_dir() / "nope.obj", "not found"); }
  SECTION("unknown extension") { expect_error(write_text("tet.xyz", tet_obj()), "unknown mesh format"); }
  SECTION("empty file") { expect_error(write_text("empty.obj", ""), "no faces"); }
  SECTION("vertices but no faces") {
    expect_error(write_text("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"), "no faces");
  }
  SECTION("OBJ cut in the middle of a vertex record") {
    const std::string full = tet_obj();
    expect_error(write_text("cut_v.obj", full.substr(0, full.find("v 0 1 0") + 4)), "truncated");
  }
  SECTION("OBJ whose faces reference vertices the file lost") {
    // Faces first, then vertices cut off after two of four: faces name vertices 3 and 4.
    std::string text;
    for (const auto& t : kTetFaces)
      text += "f " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + " " + std::to_string(t[2] + 1) + "\n";
    text += "v 0 0 0\nv 1 0 0\n";
    expect_error(write_text("lost_v.obj", text), "only 2 vertices");
  }
  SECTION("OFF ending before its declared faces") {
    const std::string full = cube_off();
    expect_error(write_text("cut.off", full.substr(0, full.find("4 1 3 7 5"))), "1 of 6 declared faces");
  }
  SECTION("OFF with its counts on the magic line (OpenMesh would read them from the vertices)") {
    expect_error(write_text("one_line.off", "OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
                 "write the vertex, face and edge counts on the next line");
    expect_error(write_text("glued.off", "OFF\n0-4 55\n"), "expected three whole counts");
  }
  SECTION("OFF records with values left over (OpenMesh would read them as the next record)") {
    expect_error(write_text("face_extra.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 86666\n"),
                 "after its 3 vertex indices");
    expect_error(write_text("vertex_extra.off", "OFF\n3 1 0\n0 0 0 7\n1 0 0\n0 1 0\n3 0 1 2\n"),
                 "after its three coordinates");
  }
  SECTION("binary STL missing its last bytes") {
    const std::string full = tet_binary_stl();
    expect_error(write_text("cut.stl", full.substr(0, full.size() - 10)), "84 + 50");
  }
  SECTION("binary STL with zero triangles") {
    std::string zero(84, '\0');
    expect_error(write_text("zero.stl", zero), "no faces");
  }
  SECTION("ASCII STL without its end") {
    const std::string full = tet_ascii_stl();
    expect_error(write_text("cut_ascii.stl", full.substr(0, full.size() / 2)), "truncated ASCII STL");
  }
  SECTION("PLY with fewer faces than declared") {
    const std::string full = tet_ply();
    expect_error(write_text("cut.ply", full.substr(0, full.rfind("3 "))), "truncated");
  }
  SECTION("binary PLY missing its last face") {
    const std::string full = tet_binary_ply();
    expect_error(write_text("cut_bin.ply", full.substr(0, full.size() - 13)), "truncated");
  }
  // OpenMesh's PLY reader hangs on a negative or huge list count: the body is walked first.
  SECTION("binary PLY whose first face declares 255 vertices: runs past the end") {
    std::string bin = tet_binary_ply();
    bin[bin.find("end_header\n") + 11 + 4 * 12] = '\xff';  // the count byte of face 0
    expect_error(write_text("long_face.ply", bin), "ends inside face 0");
  }
  SECTION("binary PLY with a negative int list count") {
    std::string bin =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1\nproperty list int int vertex_indices\nend_header\n";
    const float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const int face[4] = {-5, 0, 1, 2};
    bin.append(reinterpret_cast<const char*>(v), sizeof v);
    bin.append(reinterpret_cast<const char*>(face), sizeof face);
    expect_error(write_text("neg_count.ply", bin), "face 0 declares -5 entries");
  }
  SECTION("ASCII PLY: a list count larger than its line, a negative one, a two-vertex face, a word") {
    const std::string full = tet_ply();
    const std::size_t first_face = full.find("3 ", full.find("end_header"));
    std::string text = full;
    text.replace(first_face, 1, "200");
    expect_error(write_text("count_200.ply", text), "declares 200 values, the line holds 3");
    text = full;
    text.replace(first_face, 1, "-4");
    expect_error(write_text("count_neg.ply", text), "declares -4 entries");
    text = full;
    text.replace(first_face, 1, "2");
    expect_error(write_text("count_2.ply", text), "declares 2 entries");
    text = full;
    text.replace(full.find("\n", full.find("end_header")) + 1, 1, "x");
    expect_error(write_text("word.ply", text), "is not a number");
  }
  SECTION("NaN vertex in OBJ: names the vertex and the line") {
    std::string text = tet_obj();
    text.replace(text.find("v 0 1 0"), 7, "v 0 nan 0");
    const fs::path p = write_text("nan.obj", text);
    try {
      load_mesh(p.string(), opt);
      FAIL("no error");
    } catch (const InputError& e) {
      CHECK(e.line() == 3);  // third vertex record is the third line
      CHECK(e.detail() == "vertex 2 is not finite");
    }
  }
  SECTION("infinite vertex in binary STL: names the vertex") {
    const fs::path p = write_text("inf.stl", tet_binary_stl(std::numeric_limits<float>::infinity()));
    expect_error(p, "is not finite");
  }
  SECTION("mesh with a hole") { expect_error(write_text("open.obj", tet_obj(false, 3)), "boundary edges"); }
}

TEST_CASE("allow_open accepts holes with a warning", "[mesh]") {
  MeshLoadOptions open;
  open.allow_open = true;
  Warnings w;
  MeshReport r;
  // Dropping one face of the tetrahedron leaves its three edges with one face each.
  const TriMesh m = load_mesh(write_text("open2.obj", tet_obj(false, 3)).string(), open, &r, &w);
  CHECK(m.faces.size() == 3);
  CHECK(r.boundary_edges == 3);
  CHECK_FALSE(r.closed());
  CHECK(mentions(w, "boundary edges"));
}

TEST_CASE("an inward-wound mesh is flipped to outward with a warning", "[mesh]") {
  Warnings w;
  const TriMesh m = load_mesh(write_text("inward.obj", tet_obj(true)).string(), {}, nullptr, &w);
  CHECK(m.signed_volume() == Approx(kTetVolume).epsilon(kExactTol));
  CHECK(mentions(w, "flipped"));
}

TEST_CASE("validate_mesh counts each kind of defect", "[mesh]") {
  TriMesh tet;
  for (int i = 0; i < 4; ++i) tet.vertices.push_back(tet_vertex(i));
  for (const auto& t : kTetFaces) tet.faces.emplace_back(t[0], t[1], t[2]);
  const MeshReport clean = validate_mesh(tet);
  CHECK(clean.closed());
  CHECK(clean.consistently_oriented());
  CHECK(clean.euler_characteristic == 2);  // 4 - 6 + 4
  CHECK(clean.degenerate_faces == 0);
  CHECK(clean.summary().find("closed, consistently oriented, Euler characteristic 2") == 0);

  SECTION("one face flipped: its three edges run the same way as their neighbours'") {
    TriMesh m = tet;
    std::swap(m.faces[3][1], m.faces[3][2]);
    CHECK(validate_mesh(m).inconsistent_edges == 3);
    CHECK(validate_mesh(m).closed());
  }
  SECTION("a fifth triangle on edge (0,1) makes it non-manifold and adds two boundary edges") {
    TriMesh m = tet;
    m.vertices.emplace_back(0.5, -1, 0);
    m.faces.emplace_back(1, 0, 4);
    const MeshReport r = validate_mesh(m);
    CHECK(r.nonmanifold_edges == 1);
    CHECK(r.boundary_edges == 2);  // (0,4) and (4,1)
    CHECK_FALSE(r.closed());
  }
  SECTION("degenerate faces and unreferenced vertices") {
    TriMesh m = tet;
    m.faces.emplace_back(0, 0, 1);     // repeated vertex
    m.vertices.emplace_back(2, 0, 0);  // collinear with 0 and 1
    m.faces.emplace_back(0, 1, 4);     // zero area
    m.vertices.emplace_back(9, 9, 9);  // in no face
    const MeshReport r = validate_mesh(m);
    CHECK(r.degenerate_faces == 2);
    CHECK(r.unreferenced_vertices == 1);
  }
}

TEST_CASE("measures, bounds and rigid transforms of a mesh", "[mesh]") {
  TriMesh tet;
  for (int i = 0; i < 4; ++i) tet.vertices.push_back(tet_vertex(i));
  for (const auto& t : kTetFaces) tet.faces.emplace_back(t[0], t[1], t[2]);
  CHECK(tet.bounds().min().isApprox(Vec3(0, 0, 0)));
  CHECK(tet.bounds().max().isApprox(Vec3(1, 1, 1)));
  // A rigid motion keeps area and volume and moves the bounds: Rz(90) maps x -> y, y -> -x,
  // then + (5, 0, 0): x in [5 - 1, 5], y in [0, 1].
  const Pose X = make_pose(Vec3(5, 0, 0), Quat(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ())));
  const TriMesh moved = tet.transformed(X);
  CHECK(moved.area() == Approx(kTetArea).epsilon(kExactTol));
  CHECK(moved.signed_volume() == Approx(kTetVolume).epsilon(kExactTol));
  CHECK((moved.bounds().min() - Vec3(4, 0, 0)).norm() < kExactTol);
  CHECK((moved.bounds().max() - Vec3(5, 1, 1)).norm() < kExactTol);
}

TEST_CASE("save_obj writes a file load_mesh reads back, atomically", "[mesh]") {
  TriMesh tet;
  for (int i = 0; i < 4; ++i) tet.vertices.push_back(tet_vertex(i) * 1e-3 + Vec3(0.1234567e-3, 0, 0));
  for (const auto& t : kTetFaces) tet.faces.emplace_back(t[0], t[1], t[2]);
  const fs::path dir = temp_dir() / "saved";
  const fs::path p = dir / "tet.obj";
  save_obj(tet, p.string());
  save_obj(tet, p.string());  // replacing an existing file works too
  const TriMesh back = load_mesh(p.string(), {});
  REQUIRE(back.vertices.size() == 4);
  CHECK(back.faces == tet.faces);
  // Written with 9 significant digits, read back by OpenMesh as 32-bit floats: for coordinates below
  // 1.2e-3 m one float ulp is 2^-33 m = 1.16e-10 m, and rounding twice stays within one ulp.
  constexpr double kWrittenPrecision = 1.2e-10;
  for (int i = 0; i < 4; ++i) CHECK((back.vertices[i] - tet.vertices[i]).norm() < kWrittenPrecision);
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir)) files += e.is_regular_file();
  CHECK(files == 1);  // no temporary left behind
}

TEST_CASE("cow.obj (closed, odd Euler characteristic) loads with a warning; spot.obj loads clean", "[mesh][data]") {
  Warnings w;
  MeshReport r;
  const TriMesh cow = load_mesh(require_data("meshes/cow.obj"), {}, &r, &w);
  CHECK(cow.faces.size() == 5804);  // SOURCE.md: 2,903 vertices, 5,804 triangles
  CHECK(r.boundary_edges == 0);
  CHECK(r.euler_characteristic % 2 != 0);
  CHECK(mentions(w, "Euler characteristic"));
  CHECK(cow.signed_volume() > 0);

  Warnings none;
  MeshReport spot_report;
  const TriMesh spot = load_mesh(require_data("meshes/spot.obj"), {}, &spot_report, &none);
  CHECK(spot.faces.size() == 5856);
  CHECK(spot_report.closed());
  CHECK(spot_report.euler_characteristic == 2);
  CHECK(none.empty());
}

}  // namespace test_mesh
