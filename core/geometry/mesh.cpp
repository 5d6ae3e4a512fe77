// Triangle meshes: loading (through OpenMesh's readers), validation, measures and OBJ output.
//
// OpenMesh parses the file formats, but its stock importer repairs topology silently (it duplicates
// vertices of faces it cannot add to its half-edge structure and drops faces with repeated vertices),
// which would hide exactly the defects validate_mesh must report. So the readers feed a small
// importer of our own that records the raw vertex and face lists as they are in the file.
//
// OpenMesh's IO header must come before any mesh kernel header.
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include "core/base/atomic_write.hpp"
#include "core/geometry/mesh.hpp"
#include "core/geometry/mesh_format_check.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace sb {

// ------------------------------------------------------------------------------------------- measures

double TriMesh::area() const {
  double a = 0;
  for (const auto& f : faces)
    a += 0.5 * (vertices[f[1]] - vertices[f[0]]).cross(vertices[f[2]] - vertices[f[0]]).norm();
  return a;
}

double TriMesh::signed_volume() const {
  // Divergence theorem: sum of the signed volumes of the tetrahedra (origin, a, b, c).
  double v = 0;
  for (const auto& f : faces) v += vertices[f[0]].dot(vertices[f[1]].cross(vertices[f[2]]));
  return v / 6.0;
}

Eigen::AlignedBox3d TriMesh::bounds() const {
  Eigen::AlignedBox3d b;
  for (const auto& p : vertices) b.extend(p);
  return b;
}

TriMesh TriMesh::transformed(const Pose& X) const {
  TriMesh out;
  out.faces = faces;  // a rigid motion keeps the winding outward
  out.vertices.reserve(vertices.size());
  for (const auto& p : vertices) out.vertices.push_back(X * p);
  return out;
}

std::string MeshReport::summary() const {
  std::ostringstream s;
  s << (closed() ? "closed" : "open") << ", "
    << (consistently_oriented() ? "consistently oriented" : "inconsistently oriented") << ", Euler characteristic "
    << euler_characteristic;
  if (boundary_edges) s << ", " << boundary_edges << " boundary edges";
  if (nonmanifold_edges) s << ", " << nonmanifold_edges << " non-manifold edges";
  if (inconsistent_edges) s << ", " << inconsistent_edges << " inconsistently oriented edges";
  if (degenerate_faces) s << ", " << degenerate_faces << " degenerate faces";
  if (unreferenced_vertices) s << ", " << unreferenced_vertices << " unreferenced vertices";
  return s.str();
}

// ------------------------------------------------------------------------------------------- validation

namespace {

// A face is degenerate when twice its area is below this fraction of the squared bounding-box diagonal
// (1e-14 relative: far below any real feature, far above round-off on flat triangles).
constexpr double kDegenerateRelativeArea = 1e-14;

std::uint64_t edge_key(int a, int b) {
  const auto lo = static_cast<std::uint64_t>(std::min(a, b));
  const auto hi = static_cast<std::uint64_t>(std::max(a, b));
  return (lo << 32) | hi;
}

}  // namespace

MeshReport validate_mesh(const TriMesh& mesh) {
  MeshReport r;
  const double diag2 = mesh.vertices.empty() ? 0.0 : mesh.bounds().diagonal().squaredNorm();
  // Every directed edge as (undirected key, direction): a consistently oriented manifold edge is
  // traversed once each way by its two faces.
  struct DirectedEdge {
    std::uint64_t key;
    bool forward;
  };
  std::vector<DirectedEdge> edges;
  edges.reserve(3 * mesh.faces.size());
  std::vector<char> referenced(mesh.vertices.size(), 0);
  for (const auto& f : mesh.faces) {
    bool repeated = f[0] == f[1] || f[1] == f[2] || f[2] == f[0];
    if (!repeated) {
      const Vec3& a = mesh.vertices[f[0]];
      const double twice_area = (mesh.vertices[f[1]] - a).cross(mesh.vertices[f[2]] - a).norm();
      if (twice_area <= kDegenerateRelativeArea * diag2) repeated = true;
    }
    if (repeated) ++r.degenerate_faces;
    for (int k = 0; k < 3; ++k) {
      referenced[f[k]] = 1;
      const int a = f[k], b = f[(k + 1) % 3];
      if (a != b) edges.push_back({edge_key(a, b), a < b});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const DirectedEdge& x, const DirectedEdge& y) {
    return x.key < y.key || (x.key == y.key && x.forward < y.forward);
  });
  std::size_t n_edges = 0;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    int forward = 0;
    while (j < edges.size() && edges[j].key == edges[i].key) forward += edges[j++].forward;
    const std::size_t uses = j - i;
    ++n_edges;
    if (uses == 1) ++r.boundary_edges;
    if (uses >= 3) ++r.nonmanifold_edges;
    if (uses == 2 && forward != 1) ++r.inconsistent_edges;
    i = j;
  }
  std::size_t n_referenced = 0;
  for (char c : referenced) n_referenced += c;
  r.unreferenced_vertices = mesh.vertices.size() - n_referenced;
  r.euler_characteristic = static_cast<int>(n_referenced) - static_cast<int>(n_edges) +
                           static_cast<int>(mesh.faces.size());
  return r;
}

// ------------------------------------------------------------------------------------------- loading

namespace {

// Records what a reader delivers; everything OpenMesh would attach besides positions is ignored.
class RawImporter final : public OpenMesh::IO::BaseImporter {
 public:
  std::vector<Vec3> points;
  std::vector<std::vector<int>> polygons;

  using VH = OpenMesh::VertexHandle;
  using FH = OpenMesh::FaceHandle;
  using HH = OpenMesh::HalfedgeHandle;
  using EH = OpenMesh::EdgeHandle;

  VH add_vertex(const OpenMesh::Vec3f& p) override { return push(Vec3(p[0], p[1], p[2])); }
  VH add_vertex(const OpenMesh::Vec3d& p) override { return push(Vec3(p[0], p[1], p[2])); }
  VH add_vertex() override { return push(Vec3::Zero()); }
  HH add_edge(VH, VH) override { return HH(); }
  FH add_face(const VHandles& vh) override {
    std::vector<int> f;
    f.reserve(vh.size());
    for (const auto& h : vh) f.push_back(h.idx());
    polygons.push_back(std::move(f));
    return FH(static_cast<int>(polygons.size()) - 1);
  }
  FH add_face(HH) override { return FH(); }
  void add_face_texcoords(FH, VH, const std::vector<OpenMesh::Vec2f>&) override {}
  void add_face_texcoords(FH, VH, const std::vector<OpenMesh::Vec3f>&) override {}
  void set_face_texindex(FH, int) override {}
  void set_point(VH v, const OpenMesh::Vec3f& p) override {
    if (v.idx() >= 0 && v.idx() < static_cast<int>(points.size())) points[v.idx()] = Vec3(p[0], p[1], p[2]);
  }
  void set_halfedge(VH, HH) override {}
  void set_normal(VH, const OpenMesh::Vec3f&) override {}
  void set_normal(VH, const OpenMesh::Vec3d&) override {}
  void set_color(VH, const OpenMesh::Vec3uc&) override {}
  void set_color(VH, const OpenMesh::Vec4uc&) override {}
  void set_color(VH, const OpenMesh::Vec3f&) override {}
  void set_color(VH, const OpenMesh::Vec4f&) override {}
  void set_texcoord(VH, const OpenMesh::Vec2f&) override {}
  void set_status(VH, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_next(HH, HH) override {}
  void set_face(HH, FH) override {}
  void request_face_texcoords2D() override {}
  void set_texcoord(HH, const OpenMesh::Vec2f&) override {}
  void set_texcoord(VH, const OpenMesh::Vec3f&) override {}
  void set_texcoord(HH, const OpenMesh::Vec3f&) override {}
  void set_status(HH, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_color(EH, const OpenMesh::Vec3uc&) override {}
  void set_color(EH, const OpenMesh::Vec4uc&) override {}
  void set_color(EH, const OpenMesh::Vec3f&) override {}
  void set_color(EH, const OpenMesh::Vec4f&) override {}
  void set_status(EH, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_normal(FH, const OpenMesh::Vec3f&) override {}
  void set_normal(FH, const OpenMesh::Vec3d&) override {}
  void set_color(FH, const OpenMesh::Vec3uc&) override {}
  void set_color(FH, const OpenMesh::Vec4uc&) override {}
  void set_color(FH, const OpenMesh::Vec3f&) override {}
  void set_color(FH, const OpenMesh::Vec4f&) override {}
  void set_status(FH, const OpenMesh::Attributes::StatusInfo&) override {}
  void add_texture_information(int, std::string) override {}
  void reserve(unsigned int nv, unsigned int, unsigned int nf) override {
    points.reserve(nv);
    polygons.reserve(nf);
  }
  size_t n_vertices() const override { return points.size(); }
  size_t n_faces() const override { return polygons.size(); }
  size_t n_edges() const override { return 0; }

 private:
  VH push(const Vec3& p) {
    points.push_back(p);
    return VH(static_cast<int>(points.size()) - 1);
  }
};

// OpenMesh reports through its own streams (to std::cerr); while we read, our InputErrors speak instead.
class SilenceOpenMesh {
 public:
  SilenceOpenMesh() {
    omerr().disable();
    omlog().disable();
    omout().disable();
  }
  ~SilenceOpenMesh() {
    // Flushing while disabled drops any partial line the readers left behind.
    omerr().flush();
    omlog().flush();
    omout().flush();
    omerr().enable();
    omlog().enable();
    omout().enable();
  }
};

void require_readable(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(path, "mesh file not found");
  if (!fs::is_regular_file(path, ec)) throw InputError(path, "mesh path is not a regular file");
  std::ifstream probe(path, std::ios::binary);
  if (!probe) throw InputError(path, "mesh file is not readable");
}

// Converts the reader's polygons to triangles (fans; the formats store planar convex polygons).
TriMesh to_trimesh(const RawImporter& raw, const std::string& path, double scale, Warnings* warnings) {
  TriMesh m;
  m.vertices.reserve(raw.points.size());
  for (std::size_t i = 0; i < raw.points.size(); ++i) {
    const Vec3& p = raw.points[i];
    if (!p.allFinite()) throw InputError(path, "vertex " + std::to_string(i) + " is not finite");
    m.vertices.push_back(scale * p);
  }
  const int nv = static_cast<int>(m.vertices.size());
  std::size_t short_polygons = 0;
  for (std::size_t fi = 0; fi < raw.polygons.size(); ++fi) {
    const auto& poly = raw.polygons[fi];
    for (int v : poly)
      if (v < 0 || v >= nv)
        throw InputError(path, "face " + std::to_string(fi) + " refers to vertex " + std::to_string(v) +
                                   " but the file has only " + std::to_string(nv) + " vertices (truncated file?)");
    if (poly.size() < 3) {
      ++short_polygons;
      continue;
    }
    for (std::size_t k = 1; k + 1 < poly.size(); ++k) m.faces.emplace_back(poly[0], poly[k], poly[k + 1]);
  }
  if (short_polygons && warnings)
    warnings->add(path + ": " + std::to_string(short_polygons) + " faces with fewer than three vertices skipped");
  return m;
}

void check_counts(const MeshFileCounts& expected, const RawImporter& raw, const std::string& path) {
  if (expected.vertices >= 0 && static_cast<long>(raw.points.size()) != expected.vertices)
    throw InputError(path, "file declares " + std::to_string(expected.vertices) + " vertices but " +
                               std::to_string(raw.points.size()) + " could be read (truncated or malformed file)");
  if (expected.faces >= 0 && static_cast<long>(raw.polygons.size()) != expected.faces)
    throw InputError(path, "file declares " + std::to_string(expected.faces) + " faces but " +
                               std::to_string(raw.polygons.size()) + " could be read (truncated or malformed file)");
}

void report_and_orient(TriMesh& mesh, MeshReport& r, const std::string& path, const MeshLoadOptions& options,
                       Warnings* warnings) {
  auto warn = [&](const std::string& m) {
    if (warnings) warnings->add(path + ": " + m);
  };
  if (r.boundary_edges) {
    if (!options.allow_open)
      throw InputError(path, "mesh has " + std::to_string(r.boundary_edges) +
                                 " boundary edges (holes); close it, or set allow_open for a best-effort SDF");
    warn("mesh has " + std::to_string(r.boundary_edges) + " boundary edges (holes); loaded because allow_open is set");
  }
  if (r.nonmanifold_edges) warn(std::to_string(r.nonmanifold_edges) + " non-manifold edges");
  if (r.inconsistent_edges) warn(std::to_string(r.inconsistent_edges) + " inconsistently oriented edges");
  if (r.degenerate_faces) warn(std::to_string(r.degenerate_faces) + " degenerate faces");
  if (r.unreferenced_vertices) warn(std::to_string(r.unreferenced_vertices) + " unreferenced vertices");
  if (r.closed() && r.euler_characteristic % 2 != 0)
    warn("Euler characteristic " + std::to_string(r.euler_characteristic) +
         " is odd: not a closed orientable 2-manifold (non-manifold vertices?)");
  if (r.boundary_edges == 0 && mesh.signed_volume() < 0) {
    for (auto& f : mesh.faces) std::swap(f[1], f[2]);
    warn("faces were oriented inward (negative volume); flipped to outward");
  }
}

}  // namespace

// Note: OpenMesh's readers parse coordinates as 32-bit floats (relative precision 6e-8: nanometres on a
// centimetre part), whatever the file holds.
TriMesh load_mesh(const std::string& path, const MeshLoadOptions& options, MeshReport* report, Warnings* warnings) {
  require_readable(path);
  if (!std::isfinite(options.scale) || options.scale <= 0)
    throw InputError(path, "mesh scale must be a positive number, got " + std::to_string(options.scale));
  const std::string ext = mesh_file_extension(path);
  const MeshFileCounts expected = scan_mesh_file(path, ext);

  RawImporter raw;
  {
    SilenceOpenMesh quiet;
    OpenMesh::IO::Options opt;
    if (!OpenMesh::IO::IOManager().read(path, raw, opt))
      throw InputError(path, "the " + ext.substr(1) + " reader could not parse this file");
  }
  check_counts(expected, raw, path);
  TriMesh mesh = to_trimesh(raw, path, options.scale, warnings);
  if (mesh.faces.empty()) throw InputError(path, "mesh has no faces");

  MeshReport r = validate_mesh(mesh);
  report_and_orient(mesh, r, path, options, warnings);
  if (report) *report = r;
  return mesh;
}

// ------------------------------------------------------------------------------------------- output

void save_obj(const TriMesh& mesh, const std::string& path) {
  std::ostringstream out;
  out << "# shearbench mesh, metres; " << mesh.vertices.size() << " vertices, " << mesh.faces.size() << " faces\n";
  std::array<char, 32> buf;
  for (const auto& p : mesh.vertices) {
    out << 'v';
    for (int k = 0; k < 3; ++k) {
      // 9 significant digits: sub-nanometre for millimetre parts, and compact files.
      auto res = std::to_chars(buf.data(), buf.data() + buf.size(), p[k], std::chars_format::general, 9);
      out << ' ' << std::string_view(buf.data(), res.ptr - buf.data());
    }
    out << '\n';
  }
  for (const auto& f : mesh.faces) out << "f " << f[0] + 1 << ' ' << f[1] + 1 << ' ' << f[2] + 1 << '\n';
  write_file_atomic(path, out.str());
}

}  // namespace sb
