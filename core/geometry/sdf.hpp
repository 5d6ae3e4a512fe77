#pragma once
// Signed distance fields: negative inside, positive outside, gradient = outward unit normal near the
// surface. Every implementation is const and thread-safe; batch queries amortise per-call setup
// (OpenVDB accessors) and are what the models call on hot paths.
#include <Eigen/Geometry>
#include <memory>
#include <span>
#include <string>

#include "core/geometry/mesh.hpp"
#include "core/geometry/pose.hpp"

namespace sb {

class Sdf {
 public:
  virtual ~Sdf() = default;
  virtual double value(const Vec3& p) const = 0;
  virtual double value_and_gradient(const Vec3& p, Vec3* gradient) const = 0;
  // Batch forms; defaults loop over the single-point calls.
  virtual void values(std::span<const Vec3> p, std::span<double> phi) const;
  virtual void values_and_gradients(std::span<const Vec3> p, std::span<double> phi, std::span<Vec3> gradient) const;
  // Box outside which values are only a lower bound (narrow band) or an extrapolation.
  virtual Eigen::AlignedBox3d bounds() const = 0;
  virtual std::string describe() const = 0;
};

using SdfPtr = std::shared_ptr<const Sdf>;

// ---- analytic fields (exact; for tests and as a fast path)
SdfPtr make_sphere_sdf(double radius, const Vec3& centre = Vec3::Zero());
// Torus about the z axis through the origin: major radius R (centre of tube), minor radius r.
SdfPtr make_torus_sdf(double major_radius, double minor_radius);
// A dome gel: the ball of radius R about (0, 0, -R) above the rim where its radius is the footprint radius,
// on a cylinder of that radius down to z = -thickness (what a spherical_cap gel's mesh describes, exactly).
SdfPtr make_spherical_cap_sdf(double radius, double footprint_radius, double thickness);
// Axis-aligned box with the given full side lengths, centred at `centre` (default: the origin).
SdfPtr make_box_sdf(const Vec3& size, const Vec3& centre = Vec3::Zero());
// Flat gel pad of tsd/1: x in [-sx/2, sx/2], y in [-sy/2, sy/2], z in [-thickness, 0].
SdfPtr make_pad_sdf(const Vec2& size, double thickness);
// Flat-ended (capped) cylinder along z, centred at the origin: radius r, full length L.
SdfPtr make_capped_cylinder_sdf(double radius, double length);
// Half-space z <= 0 (an infinite slab surface): phi = z.
SdfPtr make_halfspace_sdf();
// A field expressed in another frame: value(p_A) = inner(X_BA * p_A) where inner is given in B.
SdfPtr make_transformed_sdf(SdfPtr inner_B, const Pose& X_AB);

// ---- mesh fields (OpenVDB narrow band, sampled trilinearly)
struct MeshSdfOptions {
  double voxel_size = 0.0;    // metres; 0 picks bbox_diagonal / 200, at most 0.25 mm
  double band_width = 0.004;  // metres of exact band on each side; >= 3 mm for deep presses
  bool allow_open = false;    // best effort for meshes with holes (sign from a flood fill)
};
SdfPtr make_mesh_sdf(const TriMesh& mesh, const MeshSdfOptions& options = {});
// Unsigned distance from p to the triangle abc (what the mesh field is built from; also the tests' exact reference).
double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

// ---- a dense cache of any field on a regular grid (fast path; optional nearest-voxel lookup that
// reproduces pytorch_volumetric.CachedSDF, the lookup the HydroShear authors' code uses)
enum class GridLookup { kTrilinear, kNearest };
SdfPtr make_grid_sdf(SdfPtr source, const Eigen::AlignedBox3d& region, double voxel_size,
                     GridLookup lookup = GridLookup::kTrilinear);

}  // namespace sb
