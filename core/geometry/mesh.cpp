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

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
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

// Counts the file declares or contains, found by a scan independent of OpenMesh (-1: unknown).
struct ExpectedCounts {
  long vertices = -1;
  long faces = -1;
};

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

bool parse_doubles(std::istringstream& in, int n, double* out) {
  for (int i = 0; i < n; ++i) {
    std::string tok;
    if (!(in >> tok)) return false;
    char* end = nullptr;
    out[i] = std::strtod(tok.c_str(), &end);
    if (end == tok.c_str() || *end != '\0') return false;
  }
  return true;
}

void check_finite_at(const double* v, const std::string& path, int line, long index) {
  if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
    throw InputError(path, line, 0, "vertex " + std::to_string(index) + " is not finite");
}

// OBJ: every v record has three numbers, every f record at least three vertex references, all of them
// to vertices the file defines (a file cut short loses the vertices its faces still reference).
ExpectedCounts scan_obj(const std::string& path) {
  std::ifstream in(path);
  ExpectedCounts c{0, 0};
  long max_index = 0;
  int max_index_line = 0;
  std::string line;
  for (int line_no = 1; std::getline(in, line); ++line_no) {
    std::istringstream s(line);
    std::string tag;
    if (!(s >> tag)) continue;
    if (tag == "v") {
      double v[3];
      if (!parse_doubles(s, 3, v))
        throw InputError(path, line_no, 0, "vertex record without three numbers (truncated or malformed file)");
      check_finite_at(v, path, line_no, c.vertices);
      ++c.vertices;
    } else if (tag == "f") {
      std::string ref;
      int n = 0;
      while (s >> ref) {
        long idx = std::strtol(ref.c_str(), nullptr, 10);
        if (idx == 0) throw InputError(path, line_no, 0, "face refers to vertex '" + ref + "'");
        if (idx < 0) idx = c.vertices + 1 + idx;  // relative reference
        if (idx <= 0) throw InputError(path, line_no, 0, "face refers to a vertex before the first");
        if (idx > max_index) max_index = idx, max_index_line = line_no;
        ++n;
      }
      if (n < 3)
        throw InputError(path, line_no, 0, "face record with fewer than three vertices (truncated or malformed file)");
      ++c.faces;
    }
  }
  if (max_index > c.vertices)
    throw InputError(path, max_index_line, 0,
                     "face refers to vertex " + std::to_string(max_index) + " but the file has only " +
                         std::to_string(c.vertices) + " vertices (truncated file?)");
  return c;
}

// OFF: the header declares the counts; the body must hold that many complete records.
ExpectedCounts scan_off(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  int line_no = 0;
  auto next_record = [&](std::istringstream& s) {
    while (std::getline(in, line)) {
      ++line_no;
      const auto hash = line.find('#');
      if (hash != std::string::npos) line.resize(hash);
      if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
      s = std::istringstream(line);
      return true;
    }
    return false;
  };
  std::istringstream s;
  if (!next_record(s)) throw InputError(path, "empty OFF file");
  std::string magic;
  s >> magic;
  // The magic is one whole token, [ST][C][N][4][n]OFF: OpenMesh strips the known prefix letters and would
  // read counts from a different place than we do after "OFF0" (fuzz_mesh, out of memory).
  static const std::regex kOffMagic("(ST)?C?N?4?n?OFF");
  if (!std::regex_match(magic, kOffMagic)) throw InputError(path, 1, 0, "not an OFF file (header '" + magic + "')");
  if (line.find("BINARY") != std::string::npos)
    // OpenMesh's binary OFF reader trusts every count in the body (per-face vertex counts included) and
    // allocates what they say (fuzz_mesh found 2 GB requests); checking it would mean re-implementing it.
    throw InputError(path, 1, 0, "binary OFF is not supported: save the mesh as ASCII OFF, PLY, STL or OBJ");
  // OpenMesh reads the magic line whole and the counts from what follows it, so counts written on the
  // magic line would be read from the vertex records instead (fuzz_mesh: "OFF 0 0" then "0-4 55" made it
  // reserve (size_t)-4 faces): the counts must be the next record, three whole integers.
  std::string extra;
  if (s >> extra)
    throw InputError(
        path, 1, 0,
        "OFF header: '" + extra + "' after '" + magic + "'; write the vertex, face and edge counts on the next line");
  if (!next_record(s)) throw InputError(path, line_no, 0, "OFF header without vertex, face and edge counts");
  ExpectedCounts c;
  long counts[3] = {0, 0, 0};
  for (int k = 0; k < 3; ++k) {
    std::string tok;
    const bool have = static_cast<bool>(s >> tok);
    const auto [end, ec] = have ? std::from_chars(tok.data(), tok.data() + tok.size(), counts[k])
                                : std::from_chars_result{tok.data(), std::errc::invalid_argument};
    if (!have || ec != std::errc() || end != tok.data() + tok.size())
      throw InputError(path, line_no, 0,
                       "OFF header: expected three whole counts 'vertices faces edges'" +
                           (have ? " (found '" + tok + "')" : std::string()));
  }
  if (s >> extra) throw InputError(path, line_no, 0, "OFF header: '" + extra + "' after the three counts");
  c.vertices = counts[0];
  c.faces = counts[1];
  if (c.vertices < 0 || c.faces < 0 || counts[2] < 0)  // OpenMesh would reserve (size_t)-4 records (fuzz_mesh)
    throw InputError(path, line_no, 0, "negative vertex, face or edge count in the OFF header");
  for (long i = 0; i < c.vertices; ++i) {
    double v[3];
    if (!next_record(s))
      throw InputError(path, line_no, 0,
                       "file ends after " + std::to_string(i) + " of " + std::to_string(c.vertices) +
                           " declared vertices (truncated)");
    if (!parse_doubles(s, 3, v)) throw InputError(path, line_no, 0, "vertex record without three numbers");
    check_finite_at(v, path, line_no, i);
    // OpenMesh reads the records as one stream of numbers, not line by line: a value left over on a
    // line would become the next record's first (plain "OFF" has nothing after x y z).
    std::string extra;
    if (magic == "OFF" && (s >> extra))
      throw InputError(path, line_no, 0, "vertex record has '" + extra + "' after its three coordinates");
  }
  for (long i = 0; i < c.faces; ++i) {
    if (!next_record(s))
      throw InputError(
          path, line_no, 0,
          "file ends after " + std::to_string(i) + " of " + std::to_string(c.faces) + " declared faces (truncated)");
    long n = 0;
    // A face record starts with its vertex count (>= 3). A record that does not parse must be an error
    // here: OpenMesh reads a garbage count and appends vertex handles until memory runs out (fuzz_mesh).
    if (!(s >> n) || n < 3 || n > c.vertices)
      throw InputError(path, line_no, 0,
                       "face record must start with its vertex count (3 to " + std::to_string(c.vertices) + ")");
    for (long k = 0; k < n; ++k) {
      long idx = -1;
      if (!(s >> idx))
        throw InputError(path, line_no, 0, "face record shorter than its declared " + std::to_string(n) + " vertices");
      if (idx < 0 || idx >= c.vertices)
        throw InputError(path, line_no, 0,
                         "face refers to vertex " + std::to_string(idx) + " but the file declares " +
                             std::to_string(c.vertices) + " vertices");
    }
    // A leftover value would be read by OpenMesh as the next face's count (fuzz_mesh: a 90-digit number
    // there made it append vertex handles until out of memory).
    std::string extra;
    if (s >> extra)
      throw InputError(path, line_no, 0,
                       "face record has '" + extra.substr(0, 20) + "' after its " + std::to_string(n) +
                           " vertex indices (face colours are not supported)");
  }
  return c;
}

// STL: binary files are exactly 84 + 50 n bytes; ASCII ones close every facet and the solid.
ExpectedCounts scan_stl(const std::string& path) {
  const auto size = fs::file_size(path);
  std::ifstream in(path, std::ios::binary);
  std::string head(std::min<std::uintmax_t>(size, 84), '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  if (size >= 84) {
    std::uint32_t n = 0;
    std::memcpy(&n, head.data() + 80, 4);
    if (size == 84 + 50ull * n) return {-1, static_cast<long>(n)};
  }
  if (head.rfind("solid", 0) != 0)
    throw InputError(
        path, "truncated binary STL: " + std::to_string(size) + " bytes is not 84 + 50 x (declared triangle count)");
  in.seekg(0);
  std::string tok;
  long facets = 0, endfacets = 0;
  bool endsolid = false;
  while (in >> tok) {
    if (tok == "facet")
      ++facets;
    else if (tok == "endfacet")
      ++endfacets;
    else if (tok.rfind("endsolid", 0) == 0)
      endsolid = true;
  }
  if (!endsolid || facets != endfacets)
    throw InputError(path, "truncated ASCII STL: " + std::to_string(facets) + " facets opened, " +
                               std::to_string(endfacets) + " closed" + (endsolid ? "" : ", no endsolid"));
  return {-1, facets};
}

// The record layout a PLY header declares, for walking its body.
struct PlyProperty {
  std::string name, type, count_type;  // count_type empty: a scalar property
};
struct PlyElement {
  std::string name;
  long count = 0;
  std::vector<PlyProperty> properties;
};

// Most vertices a list (a polygon) may declare: a larger count is a corrupt file, not a mesh (OpenMesh's
// reader hangs on a negative or huge count instead of failing).
constexpr long kMaxPlyListCount = 1 << 16;

bool ply_integer_type(const std::string& t) {
  return t != "float" && t != "double" && t != "float32" && t != "float64";
}

int ply_type_size(const std::string& t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "double" || t == "float64") return 8;
  return 4;
}

// A list count read from a binary body (integer types only; the header check rejects float counts).
long read_ply_count(const unsigned char* p, const std::string& type, bool big_endian) {
  const int n = ply_type_size(type);
  std::uint64_t u = 0;
  for (int i = 0; i < n; ++i) u |= static_cast<std::uint64_t>(p[big_endian ? i : n - 1 - i]) << (8 * (n - 1 - i));
  const bool is_signed = type == "char" || type == "int8" || type == "short" || type == "int16" || type == "int" ||
                         type == "int32";
  if (is_signed && (u >> (8 * n - 1)) != 0) return static_cast<long>(u) - (1L << (8 * n));  // two's complement
  return static_cast<long>(u);
}

void check_ply_list_count(long count, const PlyElement& e, long record, const PlyProperty& prop,
                          const std::string& path, const std::string& where) {
  const long lowest = e.name == "face" ? 3 : 0;
  if (count < lowest || count > kMaxPlyListCount)
    throw InputError(path, where + ": " + e.name + " " + std::to_string(record) + " declares " + std::to_string(count) +
                               " entries in list '" + prop.name + "' (expected " + std::to_string(lowest) + ".." +
                               std::to_string(kMaxPlyListCount) + ")");
}

// Walks a binary body record by record: every list count in range and every record inside the file.
void check_ply_binary_body(std::istream& in, const std::vector<PlyElement>& layout, bool big_endian,
                           const std::string& path) {
  const std::streampos start = in.tellg();
  std::vector<unsigned char> body((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::size_t at = 0;
  auto need = [&](std::size_t bytes, const PlyElement& e, long record) {
    if (body.size() - at < bytes)
      throw InputError(path, "binary body ends inside " + e.name + " " + std::to_string(record) + " (byte " +
                                 std::to_string(static_cast<std::uintmax_t>(start) + at) + "; truncated)");
  };
  for (const PlyElement& e : layout)
    for (long r = 0; r < e.count; ++r)
      for (const PlyProperty& prop : e.properties) {
        if (prop.count_type.empty()) {
          need(ply_type_size(prop.type), e, r);
          at += ply_type_size(prop.type);
          continue;
        }
        const int count_bytes = ply_type_size(prop.count_type);
        need(count_bytes, e, r);
        const long count = read_ply_count(&body[at], prop.count_type, big_endian);
        check_ply_list_count(count, e, r, prop, path,
                             "byte " + std::to_string(static_cast<std::uintmax_t>(start) + at));
        at += count_bytes;
        need(static_cast<std::size_t>(count) * ply_type_size(prop.type), e, r);
        at += static_cast<std::size_t>(count) * ply_type_size(prop.type);
      }
}

// Walks an ASCII body: one record per line (as every PLY writer emits), each value a number, every list
// count an integer in range followed by that many values, nothing left over.
void check_ply_ascii_body(std::istream& in, const std::vector<PlyElement>& layout, int line_no,
                          const std::string& path) {
  std::string line;
  auto number = [&](const std::string& tok, int col) {
    double v = 0;
    const auto [end, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
    if (ec != std::errc() || end != tok.data() + tok.size())
      throw InputError(path, line_no, col, "'" + tok + "' is not a number");
    return v;
  };
  for (const PlyElement& e : layout)
    for (long r = 0; r < e.count; ++r) {
      do {
        if (!std::getline(in, line))
          throw InputError(path, "file declares " + std::to_string(e.count) + " " + e.name + " records but ends at " +
                                     e.name + " " + std::to_string(r) + " (truncated)");
        ++line_no;
      } while (line.find_first_not_of(" \t\r") == std::string::npos);
      std::istringstream s(line);
      std::vector<std::string> tok;
      for (std::string t; s >> t;) tok.push_back(t);
      std::size_t k = 0;
      auto next = [&](const PlyProperty& prop) -> const std::string& {
        if (k >= tok.size())
          throw InputError(path, line_no, 0,
                           e.name + " " + std::to_string(r) + " ends before property '" + prop.name + "'");
        return tok[k++];
      };
      for (const PlyProperty& prop : e.properties) {
        if (prop.count_type.empty()) {
          number(next(prop), static_cast<int>(k) + 1);
          continue;
        }
        const double count = number(next(prop), static_cast<int>(k) + 1);
        if (count != std::floor(count))
          throw InputError(path, line_no, static_cast<int>(k), "list count '" + tok[k - 1] + "' is not an integer");
        check_ply_list_count(static_cast<long>(std::clamp(count, -1e12, 1e12)), e, r, prop, path,
                             "line " + std::to_string(line_no));
        if (tok.size() - k < static_cast<std::size_t>(count))
          throw InputError(path, line_no, static_cast<int>(k),
                           e.name + " " + std::to_string(r) + ": list '" + prop.name + "' declares " + tok[k - 1] +
                               " values, the line holds " + std::to_string(tok.size() - k));
        for (long i = 0; i < static_cast<long>(count); ++i) number(next(prop), static_cast<int>(k) + 1);
      }
      if (k != tok.size())
        throw InputError(path, line_no, static_cast<int>(k) + 1,
                         e.name + " " + std::to_string(r) + " has " + std::to_string(tok.size() - k) +
                             " values more than its properties declare");
    }
}

bool ply_known_type(const std::string& t) {
  static const char* types[] = {"char", "uchar", "short", "ushort", "int",   "uint",   "float",   "double",
                                "int8", "uint8", "int16", "uint16", "int32", "uint32", "float32", "float64"};
  for (const char* k : types)
    if (t == k) return true;
  return false;
}

// OpenMesh tokenises the header across lines and control bytes, so a header that is not plain text
// parses differently there than here (it looped on one; fuzz_mesh): plain printable ASCII only.
void check_ply_header_text(const std::string& line, int line_no, const std::string& path) {
  for (std::size_t k = 0; k < line.size(); ++k) {
    const unsigned char ch = static_cast<unsigned char>(line[k]);
    if ((ch < 0x20 && ch != '\t') || ch >= 0x7f)
      throw InputError(path, line_no, static_cast<int>(k) + 1, "PLY header: a byte that is not text");
  }
}

// One 'property' line (after the keyword, in `s`) added to `element`; returns the bytes it adds to a
// fixed-size record (a face's list counted as a triangle, the smallest polygon).
std::uintmax_t parse_ply_property(std::istringstream& s, bool face, PlyElement& element, int line_no,
                                  const std::string& path) {
  std::string type, count_type, item_type;
  s >> type;
  if (type == "list") {
    s >> count_type >> item_type;
    if (!ply_known_type(count_type) || !ply_known_type(item_type))
      throw InputError(path, line_no, 0, "PLY header: unknown list types '" + count_type + " " + item_type + "'");
    std::string name, extra;
    if (!(s >> name) || (s >> extra))  // OpenMesh loops on a property without a name (fuzz_mesh)
      throw InputError(path, line_no, 0, "PLY header: expected 'property list <type> <type> <name>'");
    if (!ply_integer_type(count_type))
      throw InputError(path, line_no, 0, "PLY header: list count type '" + count_type + "' is not an integer");
    element.properties.push_back({name, item_type, count_type});
    return ply_type_size(count_type) + (face ? 3 * ply_type_size(item_type) : 0);
  }
  if (!ply_known_type(type)) throw InputError(path, line_no, 0, "PLY header: unknown property type '" + type + "'");
  std::string name, extra;
  if (!(s >> name) || (s >> extra)) throw InputError(path, line_no, 0, "PLY header: expected 'property <type> <name>'");
  element.properties.push_back({name, type, ""});
  return ply_type_size(type);
}

// PLY: the header declares the element counts. OpenMesh's PLY reader invents records at the end of a
// cut file, so the body is measured here: ASCII files need one line per declared element, binary
// ones at least the bytes of fixed-size records (faces counted as triangles, the smallest polygon).
ExpectedCounts scan_ply(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  ExpectedCounts c;
  int line_no = 0;
  bool ascii = false, big_endian = false;
  std::vector<PlyElement> layout;
  std::uintmax_t min_body_bytes = 0, record_bytes = 0;
  long current_count = 0;
  std::string current;
  auto close_element = [&] { min_body_bytes += record_bytes * static_cast<std::uintmax_t>(current_count); };
  // The header is checked against the PLY grammar before OpenMesh sees it: its reader crashes on a
  // property with no element before it or an unknown keyword (found by fuzz_mesh).
  bool have_format = false;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream s(line);
    std::string word;
    s >> word;
    check_ply_header_text(line, line_no, path);
    if (line_no == 1) {
      if (word != "ply") throw InputError(path, 1, 0, "not a PLY file (no 'ply' magic)");
      continue;
    }
    if (word == "format") {
      std::string f, version;
      s >> f >> version;
      if (f != "ascii" && f != "binary_little_endian" && f != "binary_big_endian")
        throw InputError(path, line_no, 0, "unknown PLY format '" + f + "'");
      if (version != "1.0") throw InputError(path, line_no, 0, "unsupported PLY version '" + version + "'");
      ascii = f == "ascii";
      big_endian = f == "binary_big_endian";
      have_format = true;
    } else if (word == "comment" || word == "obj_info" || word.empty()) {
      // free text
    } else if (!have_format) {
      throw InputError(path, line_no, 0, "PLY header: '" + word + "' before the format line");
    } else if (word == "element") {
      close_element();
      current_count = -1;
      std::string rest;
      // A failed extraction sets the count to 0, which OpenMesh's reader then loops on: check the stream.
      if (!(s >> current >> current_count) || current_count < 0 || (s >> rest))
        throw InputError(path, line_no, 0, "PLY header: expected 'element <name> <count>'");
      record_bytes = 0;
      layout.push_back({current, current_count, {}});
      if (current == "vertex") c.vertices = current_count;
      if (current == "face") c.faces = current_count;
    } else if (word == "property") {
      if (current.empty()) throw InputError(path, line_no, 0, "PLY header: property before any element");
      record_bytes += parse_ply_property(s, current == "face", layout.back(), line_no, path);
    } else if (word == "end_header") {
      close_element();
      if (ascii) {
        check_ply_ascii_body(in, layout, line_no, path);
      } else {
        const auto body = fs::file_size(path) - static_cast<std::uintmax_t>(in.tellg());
        if (body < min_body_bytes)
          throw InputError(path, "binary body of " + std::to_string(body) + " bytes is shorter than the " +
                                     std::to_string(min_body_bytes) + " its header declares (truncated)");
        check_ply_binary_body(in, layout, big_endian, path);
      }
      return c;
    } else {
      throw InputError(path, line_no, 0, "PLY header: unknown keyword '" + word + "'");
    }
  }
  throw InputError(path, line_no, 0, "PLY header without end_header (truncated)");
}

ExpectedCounts scan_file(const std::string& path, const std::string& ext) {
  if (ext == ".obj") return scan_obj(path);
  if (ext == ".off") return scan_off(path);
  if (ext == ".stl") return scan_stl(path);
  if (ext == ".ply") return scan_ply(path);
  throw InputError(path, "unknown mesh format '" + ext + "' (expected .obj, .stl, .ply or .off)");
}

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

void check_counts(const ExpectedCounts& expected, const RawImporter& raw, const std::string& path) {
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
  const std::string ext = lower_extension(path);
  const ExpectedCounts expected = scan_file(path, ext);

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
