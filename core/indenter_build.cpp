// Indenters from scene descriptions: mesh (procedural or loaded), surface samples, and SDF. Kept apart
// from indenter.cpp because it is the one place that needs the mesh SDF (OpenVDB) as well.
#include <filesystem>
#include <stdexcept>

#include "core/data_root.hpp"
#include "core/indenter.hpp"

namespace sb {

namespace {

struct ShapeAndField {
  TriMesh mesh;
  SdfPtr analytic;  // null when the shape has no exact field (cylinder, loaded meshes)
};

ShapeAndField make_shape(const IndenterSpec& spec, const std::string& data_root, const std::string& base_dir,
                         Warnings* warnings) {
  if (spec.shape == "sphere") return {make_sphere_mesh(spec.radius_m), make_sphere_sdf(spec.radius_m)};
  if (spec.shape == "torus")
    return {make_torus_mesh(spec.radius_m, spec.minor_radius_m), make_torus_sdf(spec.radius_m, spec.minor_radius_m)};
  if (spec.shape == "cylinder") {
    // The exact field covers the sharp-edged cylinder only; a filleted one uses the mesh field.
    TriMesh mesh = make_cylinder_mesh(spec.radius_m, spec.length_m, spec.fillet_m);
    return {std::move(mesh), spec.fillet_m == 0 ? make_capped_cylinder_sdf(spec.radius_m, spec.length_m) : nullptr};
  }
  if (spec.shape == "box") return {make_box_mesh(spec.size_m), make_box_sdf(spec.size_m)};
  if (spec.shape == "mesh" || (spec.shape.empty() && !spec.mesh_path.empty())) {
    const std::string path = resolve_path(spec.mesh_path, data_root, base_dir);
    require_exists(path, "indenter mesh");
    MeshLoadOptions options;
    options.scale = spec.scale;
    options.allow_open = spec.allow_open;
    return {load_mesh(path, options, nullptr, warnings), nullptr};
  }
  throw InputError("indenter", "unknown indenter shape '" + spec.shape +
                                   "' (expected sphere, torus, cylinder, box or mesh)");
}

}  // namespace

Indenter build_indenter(const IndenterSpec& spec, const std::string& data_root, const std::string& base_dir,
                        Warnings* warnings) {
  ShapeAndField shape;
  try {
    shape = make_shape(spec, data_root, base_dir, warnings);
  } catch (const std::invalid_argument& e) {  // a procedural shape with impossible dimensions
    throw InputError("indenter '" + spec.shape + "'", e.what());
  }
  Indenter ind;
  ind.name = spec.shape == "mesh" || spec.shape.empty() ? std::filesystem::path(spec.mesh_path).stem().string()
                                                        : spec.shape;
  ind.mesh = std::move(shape.mesh);
  ind.samples = poisson_disk_samples(ind.mesh, spec.sample_spacing_m);
  if (spec.analytic_sdf && shape.analytic) {
    ind.sdf = shape.analytic;
  } else {
    MeshSdfOptions options;
    options.allow_open = spec.allow_open;
    ind.sdf = make_mesh_sdf(ind.mesh, options);
  }
  return ind;
}

}  // namespace sb
