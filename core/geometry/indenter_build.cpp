// Indenters from scene descriptions. Kept apart from the rest of the indenter code because it is the
// one place that needs the mesh SDF (OpenVDB) as well.
#include <algorithm>
#include <filesystem>

#include "core/geometry/indenter.hpp"
#include "core/geometry/sdf_cache.hpp"

namespace sb {

namespace {
constexpr double kIndenterSdfBand = 0.003;        // metres
constexpr double kIndenterSdfMinVoxel = 0.1e-3;   // metres
constexpr double kIndenterSdfMaxVoxel = 0.25e-3;  // metres
}  // namespace

Indenter build_indenter(const IndenterSpec& spec, const std::string& data_root, const std::string& base_dir,
                        Warnings* warnings) {
  Indenter ind;
  const bool from_file = spec.shape == "mesh" || (spec.shape.empty() && !spec.mesh_path.empty());
  ind.name = from_file ? std::filesystem::path(spec.mesh_path).stem().string() : spec.shape;
  ind.mesh = make_indenter_mesh(spec, data_root, base_dir, warnings);
  ind.samples = poisson_disk_samples(ind.mesh, spec.sample_spacing_m);
  if (spec.analytic_sdf) ind.sdf = make_analytic_indenter_sdf(spec);
  if (spec.analytic_sdf && !ind.sdf) ind.sdf = box_mesh_sdf(ind.mesh);
  if (!ind.sdf) {
    MeshSdfOptions options;
    options.allow_open = spec.allow_open;
    // Indenters need the band only as deep as the deepest press (>= 3 mm) and a voxel no finer than
    // 0.1 mm: a finer default (bbox/200) made small meshes cost millions of voxels and seconds to build.
    options.band_width = kIndenterSdfBand;
    const double diagonal = ind.mesh.bounds().diagonal().norm();
    options.voxel_size = std::clamp(diagonal / 200.0, kIndenterSdfMinVoxel, kIndenterSdfMaxVoxel);
    ind.sdf = cached_mesh_sdf(ind.mesh, options);  // a fit reloads its dataset: built once (sdf_cache.hpp)
  }
  return ind;
}

}  // namespace sb
