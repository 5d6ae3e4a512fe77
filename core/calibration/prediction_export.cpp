#include "core/calibration/prediction_export.hpp"

#include <filesystem>
#include <stdexcept>

#include "core/data/tsd.hpp"
#include "core/geometry/indenter.hpp"
#include "core/geometry/mesh.hpp"
#include "core/sensor/sensor.hpp"

namespace fs = std::filesystem;

namespace sb {

void write_prediction_dataset(const std::string& dir, const PredictionExport& e) {
  if (e.X_EI.size() != e.disp_px.size() || (!e.t_s.empty() && e.t_s.size() != e.X_EI.size()))
    throw std::invalid_argument("write_prediction_dataset: one pose, one field (and one time) per frame");
  Dataset ds;
  ds.name = e.name;
  ds.kind = "synthetic";
  ds.license = "CC0-1.0";
  ds.provenance = e.provenance;
  ds.camera = e.sensor->camera;
  ds.gel = e.sensor->gel;
  if (gel_surface_is_mesh(ds.gel.surface)) ds.gel.surface = "meshes/gel.obj";
  ds.markers_rest_px = e.sensor->markers_rest_px;
  if (!e.shearbench.is_null()) ds.extra["shearbench"] = e.shearbench;
  const std::string indenter_name = e.indenter->name.empty() ? "indenter" : e.indenter->name;
  const std::string mesh_rel = "meshes/" + indenter_name + ".obj";
  ds.indenters[indenter_name] = TsdIndenter{mesh_rel, nlohmann::json::object()};
  TsdSampleInfo info;
  info.id = e.sample_id;
  info.motion = e.motion;
  info.indenter = indenter_name;
  info.split = "validation";
  info.dt_s = e.dt_s;
  ds.samples.push_back(info);
  ds.dir = dir;
  SampleData data;
  for (std::size_t k = 0; k < e.X_EI.size(); ++k)
    data.push_pose(e.t_s.empty() ? static_cast<double>(k) * e.dt_s : e.t_s[k], e.X_EI[k]);
  data.markers_px = e.disp_px;
  fs::create_directories(fs::path(dir) / "meshes");
  save_obj(e.indenter->mesh, (fs::path(dir) / mesh_rel).string());
  if (gel_surface_is_mesh(ds.gel.surface)) save_obj(e.sensor->gel_mesh, (fs::path(dir) / ds.gel.surface).string());
  write_dataset(dir, ds, {data});
}

std::vector<std::vector<Vec2>> predict_along(ShearModel& model, const std::vector<Pose>& path, double dt_s,
                                             const std::atomic<bool>* cancel,
                                             const std::function<void(std::size_t)>& on_steps) {
  std::vector<std::vector<Vec2>> fields;
  fields.reserve(path.size());
  model.reset();
  FieldOutput out;
  for (const Pose& X : path) {
    if (cancel != nullptr && cancel->load(std::memory_order_relaxed)) return {};
    model.step(X, dt_s, &out);
    fields.push_back(out.disp_px);
    if (on_steps && fields.size() % kPredictReportEvery == 0) on_steps(fields.size());
  }
  if (on_steps && fields.size() % kPredictReportEvery != 0) on_steps(fields.size());
  return fields;
}

}  // namespace sb
