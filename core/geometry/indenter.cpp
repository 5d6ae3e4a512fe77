// Procedural indenter meshes and Poisson-disk surface sampling.
#include "core/geometry/indenter.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <stdexcept>

namespace sb {

namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what);
}

// For shapes star-shaped about the origin: make every face's normal point away from the origin.
void orient_away_from_origin(TriMesh& m) {
  for (auto& f : m.faces) {
    const Vec3& a = m.vertices[f[0]];
    const Vec3 n = (m.vertices[f[1]] - a).cross(m.vertices[f[2]] - a);
    const Vec3 centroid = (a + m.vertices[f[1]] + m.vertices[f[2]]) / 3.0;
    if (n.dot(centroid) < 0) std::swap(f[1], f[2]);
  }
}

// Surface of revolution about z of a profile (rho, z) that starts and ends on the axis (rho = 0).
// Ring parameters advance counter-clockwise around z; with the profile running from the bottom pole
// to the top pole, (d/dtheta) x (d/dprofile) points outward, which fixes the winding below.
TriMesh revolve_profile(const std::vector<Vec2>& profile, int n_around) {
  TriMesh m;
  const int n_rings = static_cast<int>(profile.size()) - 2;  // interior profile points
  m.vertices.emplace_back(0, 0, profile.front().y());
  for (int k = 1; k <= n_rings; ++k)
    for (int j = 0; j < n_around; ++j) {
      const double t = 2 * M_PI * j / n_around;
      m.vertices.emplace_back(profile[k].x() * std::cos(t), profile[k].x() * std::sin(t), profile[k].y());
    }
  m.vertices.emplace_back(0, 0, profile.back().y());
  const int bottom = 0, top = static_cast<int>(m.vertices.size()) - 1;
  auto ring = [&](int k, int j) { return 1 + (k - 1) * n_around + (j % n_around); };
  for (int j = 0; j < n_around; ++j) m.faces.emplace_back(bottom, ring(1, j + 1), ring(1, j));
  for (int k = 1; k < n_rings; ++k)
    for (int j = 0; j < n_around; ++j) {
      const int a = ring(k, j), b = ring(k, j + 1), c = ring(k + 1, j + 1), d = ring(k + 1, j);
      m.faces.emplace_back(a, b, c);
      m.faces.emplace_back(a, c, d);
    }
  for (int j = 0; j < n_around; ++j) m.faces.emplace_back(ring(n_rings, j), ring(n_rings, j + 1), top);
  return m;
}

// Appends points from `from` (exclusive) towards `to` (inclusive) in n equal steps.
void append_segment(std::vector<Vec2>& profile, const Vec2& to, int n) {
  const Vec2 from = profile.back();
  for (int i = 1; i <= n; ++i) profile.push_back(from + (to - from) * (double(i) / n));
}

// Appends a circular arc about `centre` from angle a0 (exclusive) to a1 (inclusive).
void append_arc(std::vector<Vec2>& profile, const Vec2& centre, double radius, double a0, double a1, int n) {
  for (int i = 1; i <= n; ++i) {
    const double a = a0 + (a1 - a0) * i / n;
    profile.push_back(centre + radius * Vec2(std::cos(a), std::sin(a)));
  }
}

}  // namespace

// ------------------------------------------------------------------------------------------- shapes

TriMesh make_sphere_mesh(double radius, int subdivisions) {
  require(radius > 0 && std::isfinite(radius), "sphere radius must be positive");
  require(subdivisions >= 0 && subdivisions <= 8, "icosphere subdivisions must be in [0, 8]");
  // Icosahedron: the cyclic permutations of (0, +-1, +-phi).
  const double phi = (1 + std::sqrt(5.0)) / 2;
  TriMesh m;
  m.vertices = {{-1, phi, 0},  {1, phi, 0},  {-1, -phi, 0}, {1, -phi, 0}, {0, -1, phi},  {0, 1, phi},
                {0, -1, -phi}, {0, 1, -phi}, {phi, 0, -1},  {phi, 0, 1},  {-phi, 0, -1}, {-phi, 0, 1}};
  m.faces = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
             {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
             {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (auto& v : m.vertices) v.normalize();
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<int, int>, int> midpoint;
    auto mid = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      m.vertices.push_back((m.vertices[a] + m.vertices[b]).normalized());
      const int idx = static_cast<int>(m.vertices.size()) - 1;
      midpoint.emplace(key, idx);
      return idx;
    };
    std::vector<Eigen::Vector3i> finer;
    finer.reserve(4 * m.faces.size());
    for (const auto& f : m.faces) {
      const int ab = mid(f[0], f[1]), bc = mid(f[1], f[2]), ca = mid(f[2], f[0]);
      finer.emplace_back(f[0], ab, ca);
      finer.emplace_back(f[1], bc, ab);
      finer.emplace_back(f[2], ca, bc);
      finer.emplace_back(ab, bc, ca);
    }
    m.faces = std::move(finer);
  }
  for (auto& v : m.vertices) v *= radius;
  orient_away_from_origin(m);  // convex about the origin: outward = away from it
  return m;
}

TriMesh make_torus_mesh(double R, double r, int n_major, int n_minor) {
  require(r > 0 && R > r && std::isfinite(R), "torus needs 0 < minor radius < major radius");
  require(n_major >= 3 && n_minor >= 3, "torus needs at least 3 segments each way");
  TriMesh m;
  for (int i = 0; i < n_major; ++i)
    for (int j = 0; j < n_minor; ++j) {
      const double u = 2 * M_PI * i / n_major, v = 2 * M_PI * j / n_minor;
      const double rho = R + r * std::cos(v);
      m.vertices.emplace_back(rho * std::cos(u), rho * std::sin(u), r * std::sin(v));
    }
  auto idx = [&](int i, int j) { return (i % n_major) * n_minor + (j % n_minor); };
  // (dp/du) x (dp/dv) is outward (at u = v = 0: y x z = +x), so (i,j) -> (i+1,j) -> (i+1,j+1) is CCW.
  for (int i = 0; i < n_major; ++i)
    for (int j = 0; j < n_minor; ++j) {
      const int a = idx(i, j), b = idx(i + 1, j), c = idx(i + 1, j + 1), d = idx(i, j + 1);
      m.faces.emplace_back(a, b, c);
      m.faces.emplace_back(a, c, d);
    }
  return m;
}

TriMesh make_cylinder_mesh(double radius, double length, double fillet, int n_around) {
  require(radius > 0 && length > 0 && std::isfinite(radius) && std::isfinite(length),
          "cylinder radius and length must be positive");
  require(fillet >= 0 && fillet < radius && 2 * fillet < length,
          "cylinder fillet must be >= 0, below the radius and below half the length");
  require(n_around >= 3, "cylinder needs at least 3 segments around");
  // Segment counts: the rim spacing h sets the flat-end rings (near-equilateral at the rim), the side
  // uses elements four times longer than wide, the fillet arc one segment per 15 degrees at 96 around.
  const double h = 2 * M_PI * radius / n_around;
  const int n_disc = std::max(1, static_cast<int>(std::ceil((radius - fillet) / h)));
  const int n_side = std::max(1, static_cast<int>(std::ceil((length - 2 * fillet) / (4 * h))));
  const int n_fillet = std::max(2, n_around / 16);
  const double zb = -length / 2, zt = length / 2;
  std::vector<Vec2> profile{{0, zb}};
  append_segment(profile, {radius - fillet, zb}, n_disc);
  if (fillet > 0) append_arc(profile, {radius - fillet, zb + fillet}, fillet, -M_PI / 2, 0, n_fillet);
  append_segment(profile, {radius, zt - fillet}, n_side);
  if (fillet > 0) append_arc(profile, {radius - fillet, zt - fillet}, fillet, 0, M_PI / 2, n_fillet);
  append_segment(profile, {0, zt}, n_disc);
  return revolve_profile(profile, n_around);
}

TriMesh make_box_mesh(const Vec3& size) {
  require(size.allFinite() && size.minCoeff() > 0, "box sides must be positive");
  const Vec3 h = size / 2;
  TriMesh m;
  for (int k = 0; k < 8; ++k)
    m.vertices.emplace_back((k & 1) ? h.x() : -h.x(), (k & 2) ? h.y() : -h.y(), (k & 4) ? h.z() : -h.z());
  // Two triangles per side: quads given by their corner bit patterns, wound outward below.
  const int quads[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
  for (const auto& q : quads) {
    m.faces.emplace_back(q[0], q[1], q[2]);
    m.faces.emplace_back(q[0], q[2], q[3]);
  }
  orient_away_from_origin(m);
  return m;
}

// ------------------------------------------------------------------------------------------- sampling

namespace {

// Candidates thrown per spacing^2 of surface. Random sequential packing keeps about 0.7 points per
// spacing^2, so each accepted point sees about 57 candidates: enough to saturate the packing and to
// estimate each point's Voronoi area to about 13 % (1/sqrt(57)).
constexpr double kCandidatesPerSpacingSq = 40.0;

// Uniform double in [0, 1) from a fixed generator, the same on every platform.
class Rng {
 public:
  explicit Rng(unsigned seed) : engine_(seed) {}
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  std::uint64_t below(std::uint64_t n) { return static_cast<std::uint64_t>(uniform() * n); }

 private:
  std::mt19937_64 engine_;
};

// Spatial hash (Teschner et al. 2003): cells of side `spacing`, hashed into a power-of-two table.
// Distinct cells may share a bucket; that only adds distance checks, never misses a neighbour.
class PointHash {
 public:
  PointHash(double cell, std::size_t expected_points) : inv_cell_(1.0 / cell) {
    std::size_t n = 1024;
    while (n < 2 * expected_points) n <<= 1;
    head_.assign(n, -1);
    mask_ = n - 1;
  }
  void insert(const Vec3& p, int id) {
    const std::size_t b = bucket(cell_of(p));
    if (static_cast<std::size_t>(id) >= next_.size()) next_.resize(id + 1, -1);
    next_[id] = head_[b];
    head_[b] = id;
  }
  // Calls visit(id) for every point stored in the 27 cells around p.
  template <class Visit>
  void for_neighbours(const Vec3& p, Visit&& visit) const {
    const Eigen::Vector3i c = cell_of(p);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz)
          for (int id = head_[bucket(c + Eigen::Vector3i(dx, dy, dz))]; id >= 0; id = next_[id])
            if (!visit(id)) return;
  }

 private:
  Eigen::Vector3i cell_of(const Vec3& p) const { return (p * inv_cell_).array().floor().cast<int>(); }
  std::size_t bucket(const Eigen::Vector3i& c) const {
    const auto h = (static_cast<std::uint64_t>(static_cast<std::uint32_t>(c.x())) * 73856093u) ^
                   (static_cast<std::uint64_t>(static_cast<std::uint32_t>(c.y())) * 19349663u) ^
                   (static_cast<std::uint64_t>(static_cast<std::uint32_t>(c.z())) * 83492791u);
    return static_cast<std::size_t>(h) & mask_;
  }
  double inv_cell_;
  std::size_t mask_ = 0;
  std::vector<int> head_, next_;
};

struct Candidate {
  Vec3 p;
  int face;
};

// Area-stratified uniform candidates: each face gets floor(expected) points plus one more with the
// fractional probability.
std::vector<Candidate> throw_candidates(const TriMesh& mesh, const std::vector<double>& face_area, double density,
                                        Rng& rng) {
  std::vector<Candidate> c;
  double total = 0;
  for (double a : face_area) total += a;
  c.reserve(static_cast<std::size_t>(total * density * 1.05) + 16);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const double expected = face_area[f] * density;
    int n = static_cast<int>(expected);
    if (rng.uniform() < expected - n) ++n;
    const Vec3& a = mesh.vertices[mesh.faces[f][0]];
    const Vec3& b = mesh.vertices[mesh.faces[f][1]];
    const Vec3& d = mesh.vertices[mesh.faces[f][2]];
    for (int i = 0; i < n; ++i) {
      // Uniform on the triangle: sqrt of the first variate undoes the density growth towards b-d.
      const double s = std::sqrt(rng.uniform()), t = rng.uniform();
      c.push_back({(1 - s) * a + s * (1 - t) * b + s * t * d, static_cast<int>(f)});
    }
  }
  return c;
}

// A random order in which to throw the candidates (they stay in face order, which keeps the area pass
// below walking the grid coherently).
std::vector<std::uint32_t> random_order(std::size_t n, Rng& rng) {
  std::vector<std::uint32_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = static_cast<std::uint32_t>(i);
  for (std::size_t i = n; i > 1; --i) std::swap(order[i - 1], order[rng.below(i)]);
  return order;
}

int nearest_by_scan(const std::vector<Vec3>& points, const Vec3& p) {
  int best = 0;
  for (std::size_t k = 1; k < points.size(); ++k)
    if ((points[k] - p).squaredNorm() < (points[best] - p).squaredNorm()) best = static_cast<int>(k);
  return best;
}

}  // namespace

SurfaceSamples poisson_disk_samples(const TriMesh& mesh, double spacing_m, unsigned seed) {
  require(spacing_m > 0 && std::isfinite(spacing_m), "sample spacing must be positive");
  SurfaceSamples out;
  if (mesh.empty()) return out;
  std::vector<double> face_area(mesh.faces.size());
  std::vector<Vec3> face_normal(mesh.faces.size());
  double total_area = 0;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const Vec3& a = mesh.vertices[mesh.faces[f][0]];
    const Vec3 n = (mesh.vertices[mesh.faces[f][1]] - a).cross(mesh.vertices[mesh.faces[f][2]] - a);
    face_area[f] = 0.5 * n.norm();
    face_normal[f] = face_area[f] > 0 ? Vec3(n.normalized()) : Vec3::UnitZ();
    total_area += face_area[f];
  }
  if (total_area <= 0) return out;

  Rng rng(seed);
  const double s2 = spacing_m * spacing_m;
  const std::vector<Candidate> cand = throw_candidates(mesh, face_area, kCandidatesPerSpacingSq / s2, rng);
  if (cand.empty()) return out;

  // Dart throwing in random order: accept a candidate when no accepted point lies closer than the
  // spacing. Accepted positions are kept compact: the neighbour tests touch only them.
  PointHash grid(spacing_m, static_cast<std::size_t>(total_area / s2) + 1);
  std::vector<Vec3> p_acc;
  std::vector<int> face_acc;
  for (std::uint32_t i : random_order(cand.size(), rng)) {
    const Vec3& p = cand[i].p;
    bool free = true;
    grid.for_neighbours(p, [&](int id) {
      free = (p_acc[id] - p).squaredNorm() >= s2;
      return free;
    });
    if (!free) continue;
    grid.insert(p, static_cast<int>(p_acc.size()));
    p_acc.push_back(p);
    face_acc.push_back(cand[i].face);
  }

  // Voronoi areas by Monte Carlo: every candidate is an equal share of the area and belongs to its
  // nearest accepted point (always within the spacing: either itself or the point that rejected it).
  const double share = total_area / static_cast<double>(cand.size());
  out.area_m2.assign(p_acc.size(), 0.0);
  for (const auto& c : cand) {
    int best = -1;
    double best_d2 = 4 * s2;
    grid.for_neighbours(c.p, [&](int id) {
      const double d2 = (p_acc[id] - c.p).squaredNorm();
      if (d2 < best_d2) best_d2 = d2, best = id;
      return true;
    });
    if (best < 0) best = nearest_by_scan(p_acc, c.p);  // unreachable by construction; never drop area
    out.area_m2[best] += share;
  }
  out.n_IS.reserve(p_acc.size());
  for (int f : face_acc) out.n_IS.push_back(face_normal[f]);
  out.p_IS = std::move(p_acc);
  return out;
}

}  // namespace sb
