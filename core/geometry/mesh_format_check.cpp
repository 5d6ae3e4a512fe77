// The mesh file checks that run before OpenMesh reads a file (mesh_format_check.hpp).
//
// OpenMesh's readers accept cut or corrupt files (they invent records, loop on bad headers or hang on huge list
// counts), so each format is scanned here first, independently of OpenMesh, for what the file declares or holds.
#include "core/geometry/mesh_format_check.hpp"

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

#include "core/base/error.hpp"

namespace fs = std::filesystem;

namespace sb {

std::string mesh_file_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

namespace {

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
MeshFileCounts scan_obj(const std::string& path) {
  std::ifstream in(path);
  MeshFileCounts c{0, 0};
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
MeshFileCounts scan_off(const std::string& path) {
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
  MeshFileCounts c;
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
MeshFileCounts scan_stl(const std::string& path) {
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
MeshFileCounts scan_ply(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  MeshFileCounts c;
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

}  // namespace

MeshFileCounts scan_mesh_file(const std::string& path, const std::string& ext) {
  if (ext == ".obj") return scan_obj(path);
  if (ext == ".off") return scan_off(path);
  if (ext == ".stl") return scan_stl(path);
  if (ext == ".ply") return scan_ply(path);
  throw InputError(path, "unknown mesh format '" + ext + "' (expected .obj, .stl, .ply or .off)");
}

}  // namespace sb
