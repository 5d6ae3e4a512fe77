// Indenters from scene descriptions. Kept apart from the rest of the indenter code because it is the
// one place that needs the mesh SDF (OpenVDB) as well.
#include <filesystem>

#include "core/indenter.hpp"

namespace sb {

Indenter build_indenter(const IndenterSpec& spec, const std::string& data_root, const std::string& base_dir,
                        Warnings* warnings) {
  Indenter ind;
  const bool from_file = spec.shape == "mesh" || (spec.shape.empty() && !spec.mesh_path.empty());
  ind.name = from_file ? std::filesystem::path(spec.mesh_path).stem().string() : spec.shape;
  ind.mesh = make_indenter_mesh(spec, data_root, base_dir, warnings);
  ind.samples = poisson_disk_samples(ind.mesh, spec.sample_spacing_m);
  if (spec.analytic_sdf) ind.sdf = make_analytic_indenter_sdf(spec);
  if (!ind.sdf) {
    MeshSdfOptions options;
    options.allow_open = spec.allow_open;
    ind.sdf = make_mesh_sdf(ind.mesh, options);
  }
  return ind;
}

}  // namespace sb
