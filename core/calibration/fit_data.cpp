#include "core/calibration/fit_data.hpp"

#include <filesystem>

namespace sb {

std::shared_ptr<const Sensor> dataset_sensor(const Dataset& ds) {
  if (!gel_surface_is_mesh(ds.gel.surface))
    return std::make_shared<const Sensor>(make_sensor(ds.camera, ds.gel, ds.markers_rest_px));
  GelSpec gel = ds.gel;
  gel.surface = (std::filesystem::path(ds.dir) / ds.gel.surface).string();
  const TriMesh gel_E = gelsight_mini_gel_in_E(gel.surface);
  return std::make_shared<const Sensor>(make_sensor(ds.camera, gel, ds.markers_rest_px, &gel_E));
}

std::map<std::string, std::shared_ptr<const Indenter>> dataset_indenters(const Dataset& ds,
                                                                         const std::string& data_root,
                                                                         const std::string& split, Warnings* warnings) {
  std::map<std::string, std::shared_ptr<const Indenter>> out;
  for (const auto& s : ds.samples) {
    if ((!split.empty() && s.split != split) || out.count(s.indenter)) continue;
    IndenterSpec spec;
    spec.shape = "mesh";
    spec.mesh_path = std::filesystem::absolute(ds.mesh_path(s.indenter)).string();  // mesh_path includes ds.dir
    auto ind = std::make_shared<Indenter>(build_indenter(spec, data_root, ds.dir, warnings));
    ind->name = s.indenter;
    out[s.indenter] = std::move(ind);
  }
  return out;
}

FitSample to_fit_sample(const TsdSampleInfo& info, const SampleData& data, std::shared_ptr<const Indenter> indenter) {
  FitSample s;
  s.id = info.id;
  s.motion = info.motion;
  s.split = info.split;
  s.dt_s = info.dt_s;
  s.X_EI = data.poses();
  s.meas_px = data.markers_px;
  s.indenter = std::move(indenter);
  return s;
}

FitData load_calibration_data(const Dataset& ds, const std::string& data_root, Warnings* warnings) {
  FitData d;
  d.sensor = dataset_sensor(ds);
  d.indenters = dataset_indenters(ds, data_root, "calibration", warnings);
  for (const auto& info : ds.samples) {
    if (info.split != "calibration") continue;  // the split rule: validation files are never opened
    d.samples.push_back(to_fit_sample(info, read_sample(ds, info.id, warnings), d.indenters.at(info.indenter)));
  }
  if (d.samples.empty()) throw InputError(ds.json_path(), "no samples in the calibration split to fit");
  return d;
}

}  // namespace sb

namespace sb {

nlohmann::json fit_file_json(const std::vector<CalibrationResult>& results, const Dataset& ds, const FitOptions& o) {
  nlohmann::json j = nlohmann::json::object();
  nlohmann::json models = nlohmann::json::object();
  for (const auto& r : results) {
    j[r.model_id] = r.params.to_json();
    models[r.model_id] = r.report_json();
  }
  j["_fit"] = {{"format", "shearbench-fit/1"},
               {"dataset", ds.dir},
               {"dataset_name", ds.name},
               {"split", "calibration"},
               {"robust", to_string(o.robust)},
               {"robust_scale_px", o.robust_scale_px},
               {"joint", o.joint},
               {"fit_px_scale", o.fit_px_scale},
               {"hold", o.hold},
               {"models", models}};
  return j;
}

}  // namespace sb
