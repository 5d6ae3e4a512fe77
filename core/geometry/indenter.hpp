#pragma once
// An indenter: its mesh (frame I), its SDF phi_I, and Poisson-disk surface points with outward
// normals and the area each represents (what HydroShear tracks).
#include <string>
#include <vector>

#include "core/geometry/mesh.hpp"
#include "core/geometry/sdf.hpp"

namespace sb {

struct SurfaceSamples {
  std::vector<Vec3> p_IS;       // points on the surface, in I
  std::vector<Vec3> n_IS;       // outward unit normals
  std::vector<double> area_m2;  // area each point represents; sums to the mesh area
};

// Poisson-disk sampling with minimum spacing `spacing_m` (default 0.75 mm as in HydroShear).
// Deterministic for a given seed.
SurfaceSamples poisson_disk_samples(const TriMesh& mesh, double spacing_m = 0.75e-3, unsigned seed = 1);

struct Indenter {
  std::string name;
  TriMesh mesh;  // in I
  SdfPtr sdf;    // phi_I, in I
  SurfaceSamples samples;
};

// ---- procedural meshes (written to assets/ by `shearbench assets`), all centred at the origin of I
TriMesh make_sphere_mesh(double radius, int subdivisions = 5);  // icosphere
TriMesh make_torus_mesh(double major_radius, double minor_radius, int n_major = 96, int n_minor = 48);
// Flat-ended cylinder along z, radius r, length L, the two rim edges rounded with a fillet radius.
TriMesh make_cylinder_mesh(double radius, double length, double fillet, int n_around = 96);
TriMesh make_box_mesh(const Vec3& size);

// A parsed indenter description from a scene: {"shape": "sphere", "radius_m": 0.004} or
// {"mesh": "data:meshes/cow.obj", "scale": 0.01, "transform": ...}. "data:" paths resolve through the
// data root; other relative paths against `base_dir`.
struct IndenterSpec {
  std::string shape;  // sphere | torus | cylinder | box | mesh
  double radius_m = 0.004;
  double minor_radius_m = 0.0015;
  double length_m = 0.04;
  double fillet_m = 0.0005;
  Vec3 size_m{0.01, 0.01, 0.01};
  std::string mesh_path;
  double scale = 1.0;
  bool allow_open = false;
  double sample_spacing_m = 0.75e-3;
  bool analytic_sdf = true;  // use the exact SDF where one exists (sphere, torus, box)
};

// The two halves of build_indenter, usable alone (they need no mesh SDF):
// the indenter's mesh in I (procedural, or loaded and scaled), and its exact field where the shape has
// one (sphere, torus, box, sharp-edged cylinder), else null. Bad shapes or dimensions throw InputError.
TriMesh make_indenter_mesh(const IndenterSpec& spec, const std::string& data_root, const std::string& base_dir,
                           Warnings* warnings = nullptr);
SdfPtr make_analytic_indenter_sdf(const IndenterSpec& spec);
// The exact field of a mesh that is an axis-aligned box (every vertex at a corner of its bounds, enclosing
// the bounds' volume: e.g. the TacTip import's flat surface), else null. A sampled field of a box costs a
// tree lookup per point and rounds its edges; the exact one is a few operations.
SdfPtr box_mesh_sdf(const TriMesh& mesh);

// Mesh, surface samples (spec.sample_spacing_m, seed 1) and field: the analytic one when
// spec.analytic_sdf and the shape has one, else make_mesh_sdf.
Indenter build_indenter(const IndenterSpec& spec, const std::string& data_root, const std::string& base_dir,
                        Warnings* warnings = nullptr);

}  // namespace sb
