// dataset_model_factory lives apart from evaluate.cpp because it is the part that links the built-in
// models and the mesh pipeline; the evaluation loop itself (and its tests) need neither.
#include <filesystem>
#include <map>
#include <mutex>

#include "core/calibration/evaluate.hpp"
#include "core/effects/model_spec.hpp"

namespace sb {

namespace {

// Building a mesh SDF takes seconds; evaluate --model all, fits and the GUI ask for the same dataset
// indenter many times in one process, so built indenters are kept for the life of the process. The key
// is the mesh's absolute path plus its modification time, so an edited file is rebuilt.
std::shared_ptr<const Indenter> cached_dataset_indenter(const Dataset& ds, const std::string& name,
                                                        const std::string& data_root, Warnings* warnings) {
  static std::mutex mutex;
  static std::map<std::string, std::shared_ptr<const Indenter>> cache;  // a handful per process
  const std::string path = std::filesystem::absolute(ds.mesh_path(name)).lexically_normal().string();
  std::error_code ec;
  const auto mtime = std::filesystem::last_write_time(path, ec);
  const std::string key = path + "@" + std::to_string(ec ? 0 : mtime.time_since_epoch().count());
  std::lock_guard<std::mutex> lock(mutex);
  if (auto it = cache.find(key); it != cache.end()) return it->second;
  IndenterSpec spec;
  spec.shape = "mesh";
  spec.mesh_path = path;  // already absolute: no base directory to join
  auto ind = std::make_shared<Indenter>(build_indenter(spec, data_root, "", warnings));
  ind->name = name;
  cache[key] = ind;
  return ind;
}

}  // namespace

ModelFactory dataset_model_factory(const Dataset& ds, const std::string& model_id, const nlohmann::json& params,
                                   const std::string& data_root, const std::string& params_where, Warnings* warnings) {
  ParamSet param_set = model_spec_params(model_id);
  param_set.update_from_json(params, params_where);
  std::shared_ptr<const Sensor> sensor;
  if (!gel_surface_is_mesh(ds.gel.surface)) {
    sensor = std::make_shared<const Sensor>(make_sensor(ds.camera, ds.gel, ds.markers_rest_px));
  } else {
    GelSpec gel = ds.gel;
    gel.surface = (std::filesystem::path(ds.dir) / ds.gel.surface).string();
    const TriMesh gel_E = gelsight_mini_gel_in_E(gel.surface);
    sensor = std::make_shared<const Sensor>(make_sensor(ds.camera, gel, ds.markers_rest_px, &gel_E));
  }
  // Build each indenter once, before the parallel loop, so the factory only reads shared state.
  auto indenters = std::make_shared<std::map<std::string, std::shared_ptr<const Indenter>>>();
  for (const auto& [name, entry] : ds.indenters) {
    bool used = false;
    for (const auto& s : ds.samples) used = used || s.indenter == name;
    if (!used) continue;
    (*indenters)[name] = cached_dataset_indenter(ds, name, data_root, warnings);
  }
  // One prototype per indenter, cloned per sample: building a model indexes the indenter's points (for the
  // TacTip's flat surface, 15k of them, once per sample before).
  auto prototypes = std::make_shared<std::map<std::string, std::shared_ptr<const ShearModel>>>();
  for (const auto& [name, indenter] : *indenters) {
    auto model = make_spec_model(model_id, sensor, indenter);
    model->set_params(param_set);
    (*prototypes)[name] = std::move(model);
  }
  return [prototypes](const TsdSampleInfo& info) { return prototypes->at(info.indenter)->clone(); };
}

}  // namespace sb
