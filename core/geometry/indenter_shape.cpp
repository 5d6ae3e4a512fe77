// Indenter shapes from scene descriptions: the mesh (procedural or loaded) and, where one exists, the
// exact field. Separate from indenter_build.cpp, which also needs the mesh SDF (OpenVDB).
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "core/base/data_root.hpp"
#include "core/geometry/indenter.hpp"

namespace sb {

namespace {

constexpr double kBoxMeshTolerance = 1e-9;  // relative to the box's diagonal (vertices) or volume

bool is_mesh_file(const IndenterSpec& spec) {
  return spec.shape == "mesh" || (spec.shape.empty() && !spec.mesh_path.empty());
}

TriMesh procedural_mesh(const IndenterSpec& spec) {
  if (spec.shape == "sphere") return make_sphere_mesh(spec.radius_m);
  if (spec.shape == "torus") return make_torus_mesh(spec.radius_m, spec.minor_radius_m);
  if (spec.shape == "cylinder") return make_cylinder_mesh(spec.radius_m, spec.length_m, spec.fillet_m);
  if (spec.shape == "box") return make_box_mesh(spec.size_m);
  throw InputError("indenter",
                   "unknown indenter shape '" + spec.shape + "' (expected sphere, torus, cylinder, box or mesh)");
}

}  // namespace

TriMesh make_indenter_mesh(const IndenterSpec& spec, const std::string& data_root, const std::string& base_dir,
                           Warnings* warnings) {
  if (is_mesh_file(spec)) {
    const std::string path = resolve_path(spec.mesh_path, data_root, base_dir);
    require_exists(path, "indenter mesh");
    MeshLoadOptions options;
    options.scale = spec.scale;
    options.allow_open = spec.allow_open;
    return load_mesh(path, options, nullptr, warnings);
  }
  try {
    return procedural_mesh(spec);
  } catch (const std::invalid_argument& e) {  // impossible dimensions
    throw InputError("indenter '" + spec.shape + "'", e.what());
  }
}

SdfPtr box_mesh_sdf(const TriMesh& mesh) {
  if (mesh.empty()) return nullptr;
  const Eigen::AlignedBox3d B = mesh.bounds();
  const Vec3 size = B.sizes();
  const double tol = kBoxMeshTolerance * size.norm();
  if (!(size.minCoeff() > tol)) return nullptr;
  for (const Vec3& v : mesh.vertices)
    for (int a = 0; a < 3; ++a)
      if (std::abs(v[a] - B.min()[a]) > tol && std::abs(v[a] - B.max()[a]) > tol) return nullptr;
  // Corners alone do not make a box (a tetrahedron on four of them): the mesh must enclose the whole volume.
  const double volume = size.prod();
  if (std::abs(mesh.signed_volume() - volume) > kBoxMeshTolerance * volume) return nullptr;
  return make_box_sdf(size, B.center());
}

SdfPtr make_analytic_indenter_sdf(const IndenterSpec& spec) {
  if (spec.shape == "sphere") return make_sphere_sdf(spec.radius_m);
  if (spec.shape == "torus") return make_torus_sdf(spec.radius_m, spec.minor_radius_m);
  if (spec.shape == "box") return make_box_sdf(spec.size_m);
  // The exact cylinder field has sharp rims; a filleted cylinder uses the mesh field.
  if (spec.shape == "cylinder" && spec.fillet_m == 0) return make_capped_cylinder_sdf(spec.radius_m, spec.length_m);
  return nullptr;
}

}  // namespace sb
