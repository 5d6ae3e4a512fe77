// Mesh signed distance fields: an OpenVDB narrow-band level set sampled trilinearly.
//
// OpenVDB stays inside this translation unit (it costs ~25 s and 1 GB to compile); nothing else includes it.
//
// Field semantics (see MeshSdfOptions in sdf.hpp):
//  - The level set stores point-to-triangle distances on voxel centres within a narrow band of
//    ceil(band_width / voxel) + 1 voxels on each side; the extra voxel keeps trilinear interpolation exact
//    up to |phi| = band_width. OpenVDB finds each voxel's closest triangle by propagating candidates through
//    the band, which is approximate (measured: up to ~0.1 voxel off on a torus); we then refine every active
//    voxel by a local descent over vertex-adjacent triangles from OpenVDB's candidate (exact on smooth
//    meshes, to float precision) and keep OpenVDB's sign.
//  - value(): trilinear interpolation of the eight surrounding voxel values (OpenVDB's BoxSampler
//    stencil), in mesh-frame metres, then clamped to [-band_width, +band_width]. So outside the band the
//    value is exactly +-band_width: a lower bound of the true distance, with the correct sign.
//  - gradient: the analytic gradient of the same trilinear interpolant, normalised. Where the interpolant is
//    flat (deep outside the band, all eight values at the background) it falls back to the direction from
//    the mesh bounding-box centre, a rough outward direction.
//  - bounds(): the mesh bounding box grown by band_width.
//  - Thread safety: the grid is never modified after construction; every query (or batch) uses its own
//    unregistered ("unsafe") const accessor, which is safe for concurrent readers of a const tree.
#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/MeshToVolume.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "core/geometry/sdf.hpp"

namespace sb {
namespace {

void initialize_openvdb_once() {
  static std::once_flag flag;
  std::call_once(flag, [] { openvdb::initialize(); });
}

Eigen::AlignedBox3d bounding_box_of(const TriMesh& mesh) {
  Eigen::AlignedBox3d box;
  for (const auto& f : mesh.faces)
    for (int k = 0; k < 3; ++k) box.extend(mesh.vertices[static_cast<std::size_t>(f[k])]);
  return box;
}

double pick_voxel_size(const Eigen::AlignedBox3d& box, const MeshSdfOptions& options) {
  if (options.voxel_size > 0) return options.voxel_size;
  constexpr double kMaxAutoVoxel = 0.25e-3;  // metres
  return std::min(box.diagonal().norm() / 200.0, kMaxAutoVoxel);
}

// Faces around each vertex (compressed rows).
struct VertexFaces {
  std::vector<int> start, faces;
  explicit VertexFaces(const TriMesh& m) : start(m.vertices.size() + 1, 0) {
    for (const auto& f : m.faces)
      for (int k = 0; k < 3; ++k) ++start[static_cast<std::size_t>(f[k]) + 1];
    for (std::size_t v = 1; v < start.size(); ++v) start[v] += start[v - 1];
    faces.resize(static_cast<std::size_t>(start.back()));
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < m.faces.size(); ++i)
      for (int k = 0; k < 3; ++k)
        faces[static_cast<std::size_t>(fill[static_cast<std::size_t>(m.faces[i][k])]++)] = static_cast<int>(i);
  }
};

// Local descent from OpenVDB's candidate triangle: move to the closest of the triangles sharing a vertex
// with the current one while that brings p closer. Exact where the distance to the mesh has a single basin
// around the candidate, as on any smooth surface; never worse than the candidate.
double descend_to_closest_face(const TriMesh& m, const VertexFaces& vf, const Vec3& p, int face) {
  auto dist = [&](int f) {
    const auto& t = m.faces[static_cast<std::size_t>(f)];
    const double d = point_triangle_distance(p, m.vertices[static_cast<std::size_t>(t[0])],
                                             m.vertices[static_cast<std::size_t>(t[1])],
                                             m.vertices[static_cast<std::size_t>(t[2])]);
    return std::isfinite(d) ? d : std::numeric_limits<double>::infinity();  // degenerate triangles
  };
  double best = dist(face);
  for (int step = 0; step < 256; ++step) {
    int next = face;
    for (int k = 0; k < 3; ++k) {
      const auto v = static_cast<std::size_t>(m.faces[static_cast<std::size_t>(face)][k]);
      for (int i = vf.start[v]; i < vf.start[v + 1]; ++i) {
        const int g = vf.faces[static_cast<std::size_t>(i)];
        const double d = dist(g);
        if (d < best) best = d, next = g;
      }
    }
    if (next == face) break;
    face = next;
  }
  return best;
}

void refine_distances(openvdb::FloatGrid& grid, const openvdb::Int32Grid& closest_face, const TriMesh& mesh,
                      double voxel) {
  const VertexFaces vf(mesh);
  std::vector<openvdb::FloatTree::LeafNodeType*> leaves;
  grid.tree().getNodes(leaves);
  const int n_faces = static_cast<int>(mesh.faces.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size()), [&](const tbb::blocked_range<std::size_t>& r) {
    auto face_at = closest_face.getConstUnsafeAccessor();
    for (std::size_t l = r.begin(); l < r.end(); ++l)
      for (auto it = leaves[l]->beginValueOn(); it; ++it) {
        const openvdb::Coord c = it.getCoord();
        const int face = face_at.getValue(c);
        if (face < 0 || face >= n_faces) continue;
        const double d = descend_to_closest_face(mesh, vf, voxel * Vec3(c.x(), c.y(), c.z()), face);
        const float old = it.getValue();
        it.setValue(static_cast<float>(old < 0 ? -d : d));
      }
  });
}

class VdbMeshSdf final : public Sdf {
 public:
  using Grid = openvdb::FloatGrid;
  using Accessor = Grid::ConstUnsafeAccessor;

  VdbMeshSdf(Grid::Ptr grid, double voxel, double band, const Eigen::AlignedBox3d& mesh_box, std::size_t n_faces,
             bool open)
      : grid_(std::move(grid)),
        voxel_(voxel),
        inv_voxel_(1.0 / voxel),
        band_(band),
        mesh_box_(mesh_box),
        n_faces_(n_faces),
        open_(open) {}

  double value(const Vec3& p) const override {
    Accessor acc = grid_->getConstUnsafeAccessor();
    return clamp(sample(acc, p, nullptr));
  }
  double value_and_gradient(const Vec3& p, Vec3* g) const override {
    Accessor acc = grid_->getConstUnsafeAccessor();
    return clamp(sample(acc, p, g));
  }
  void values(std::span<const Vec3> p, std::span<double> phi) const override {
    Accessor acc = grid_->getConstUnsafeAccessor();
    for (std::size_t i = 0; i < p.size(); ++i) phi[i] = clamp(sample(acc, p[i], nullptr));
  }
  void values_and_gradients(std::span<const Vec3> p, std::span<double> phi, std::span<Vec3> g) const override {
    Accessor acc = grid_->getConstUnsafeAccessor();
    for (std::size_t i = 0; i < p.size(); ++i) phi[i] = clamp(sample(acc, p[i], &g[i]));
  }
  Eigen::AlignedBox3d bounds() const override {
    const Vec3 grow = Vec3::Constant(band_);
    return {mesh_box_.min() - grow, mesh_box_.max() + grow};
  }
  std::string describe() const override {
    std::ostringstream s;
    s << "OpenVDB mesh SDF (" << n_faces_ << " triangles, voxel " << voxel_ * 1e3 << " mm, band +-" << band_ * 1e3
      << " mm, " << grid_->activeVoxelCount() << " active voxels" << (open_ ? ", open mesh: best-effort sign" : "")
      << ")";
    return s.str();
  }

 private:
  double clamp(double v) const { return std::clamp(v, -band_, band_); }

  // Trilinear interpolation in index space (voxel centres at integer coordinates); the gradient, when asked
  // for, is the analytic gradient of the same interpolant.
  double sample(Accessor& acc, const Vec3& p, Vec3* gradient) const {
    const Vec3 x = p * inv_voxel_;
    const openvdb::Coord ijk(static_cast<int>(std::floor(x.x())), static_cast<int>(std::floor(x.y())),
                             static_cast<int>(std::floor(x.z())));
    const Vec3 t = x - Vec3(ijk.x(), ijk.y(), ijk.z());
    float c[2][2][2];
    openvdb::tools::BoxSampler::probeValues(c, acc, ijk);
    const double v = openvdb::tools::BoxSampler::trilinearInterpolation(c, openvdb::Vec3R(t.x(), t.y(), t.z()));
    if (gradient) *gradient = normalised_gradient(c, t, p);
    return v;
  }

  Vec3 normalised_gradient(const float c[2][2][2], const Vec3& t, const Vec3& p) const {
    const double tx = t.x(), ty = t.y(), tz = t.z();
    auto lerp = [](double a, double b, double s) { return a + (b - a) * s; };
    // d/dx: difference of the two x-faces, bilinear in (y, z); likewise for y and z.
    const double gx = lerp(lerp(c[1][0][0] - c[0][0][0], c[1][0][1] - c[0][0][1], tz),
                           lerp(c[1][1][0] - c[0][1][0], c[1][1][1] - c[0][1][1], tz), ty);
    const double gy = lerp(lerp(c[0][1][0] - c[0][0][0], c[0][1][1] - c[0][0][1], tz),
                           lerp(c[1][1][0] - c[1][0][0], c[1][1][1] - c[1][0][1], tz), tx);
    const double gz = lerp(lerp(c[0][0][1] - c[0][0][0], c[0][1][1] - c[0][1][0], ty),
                           lerp(c[1][0][1] - c[1][0][0], c[1][1][1] - c[1][1][0], ty), tx);
    const Vec3 g(gx, gy, gz);
    const double n = g.norm();
    if (n > 1e-6 * voxel_) return g / n;
    const Vec3 away = p - mesh_box_.center();
    return away.norm() > 0 ? Vec3(away.normalized()) : Vec3::UnitZ();
  }

  Grid::Ptr grid_;
  double voxel_, inv_voxel_, band_;
  Eigen::AlignedBox3d mesh_box_;
  std::size_t n_faces_;
  bool open_;
};

}  // namespace

// Distance from p to triangle abc (closest-point regions, Ericson, Real-Time Collision Detection 5.1.5).
double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return ap.norm();
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return bp.norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + ab * (d1 / (d1 - d3)))).norm();
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return cp.norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + ac * (d2 / (d2 - d6)))).norm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return (p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))))).norm();
  const double denom = 1.0 / (va + vb + vc);
  return (p - (a + ab * (vb * denom) + ac * (vc * denom))).norm();
}

SdfPtr make_mesh_sdf(const TriMesh& mesh, const MeshSdfOptions& options) {
  if (mesh.faces.empty()) throw std::invalid_argument("make_mesh_sdf: the mesh has no triangles");
  if (!(options.band_width > 0)) throw std::invalid_argument("make_mesh_sdf: band_width must be positive");
  initialize_openvdb_once();

  const Eigen::AlignedBox3d box = bounding_box_of(mesh);
  const double voxel = pick_voxel_size(box, options);
  if (!(voxel > 0) || !std::isfinite(voxel))
    throw std::invalid_argument("make_mesh_sdf: degenerate mesh (zero extent)");

  std::vector<openvdb::Vec3s> points;
  points.reserve(mesh.vertices.size());
  for (const auto& v : mesh.vertices)
    points.emplace_back(static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z()));
  std::vector<openvdb::Vec3I> triangles;
  triangles.reserve(mesh.faces.size());
  for (const auto& f : mesh.faces) {
    for (int k = 0; k < 3; ++k)
      if (f[k] < 0 || static_cast<std::size_t>(f[k]) >= mesh.vertices.size())
        throw std::invalid_argument("make_mesh_sdf: face index out of range");
    triangles.emplace_back(static_cast<unsigned>(f[0]), static_cast<unsigned>(f[1]), static_cast<unsigned>(f[2]));
  }

  // One more voxel than the band so that interpolation is exact up to |phi| = band_width.
  const float half_width = static_cast<float>(std::ceil(options.band_width / voxel) + 1.0);
  const auto xform = openvdb::math::Transform::createLinearTransform(voxel);
  for (auto& p : points) p = xform->worldToIndex(p);  // the adapter wants index-space points
  // meshToVolume classifies inside/outside by a flood fill of the voxelised surface, not by face
  // orientation: it tolerates non-manifold and self-intersecting (but closed) meshes such as cow.obj. For
  // open meshes it is the best effort: holes narrower than about a voxel are sealed by the voxelisation;
  // wider holes may let the "outside" flood leak in, so the sign near them is unreliable.
  openvdb::tools::QuadAndTriangleDataAdapter<openvdb::Vec3s, openvdb::Vec3I> adapter(points, triangles);
  openvdb::util::NullInterrupter interrupter;
  openvdb::Int32Grid closest_face(0);
  auto grid = openvdb::tools::meshToVolume<openvdb::FloatGrid>(interrupter, adapter, *xform, half_width, half_width, 0,
                                                               &closest_face);
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  refine_distances(*grid, closest_face, mesh, voxel);
  return std::make_shared<VdbMeshSdf>(grid, voxel, options.band_width, box, mesh.faces.size(), options.allow_open);
}

}  // namespace sb
