#include "core/data/scene.hpp"

#include <cmath>
#include <filesystem>

#include "core/base/data_root.hpp"
#include "core/base/error.hpp"
#include "core/data/json_read.hpp"
#include "core/data/sensor_json.hpp"
#include "core/data/tsd.hpp"

namespace fs = std::filesystem;

namespace sb {

using jsonin::child;

namespace {

// resolve_path at a scene's JSON pointer: a data: path with no data root is reported at the scene's
// file and entry (which file asked for data), not only at the data: path.
std::string resolve_at(const std::string& given, const std::string& data_root, const std::string& base_dir,
                       const std::string& where, const std::string& pointer) {
  try {
    return resolve_path(given, data_root, base_dir);
  } catch (const InputError& e) {
    jsonin::fail(where, pointer, "'" + given + "': " + e.detail());
  }
}

}  // namespace

Pose rpy_pose(const Vec3& xyz_m, const Vec3& rpy_deg) {
  const Vec3 a = rpy_deg * (M_PI / 180.0);
  // Extrinsic x-y-z (roll about x first, then pitch about the fixed y, then yaw about the fixed z).
  Pose X = Pose::Identity();
  X.linear() = Rz(a.z()) * Ry(a.y()) * Rx(a.x());
  X.translation() = xyz_m;
  return X;
}

std::vector<double> trajectory_times(const std::vector<Keyframe>& keyframes, double dt_s) {
  if (keyframes.empty()) return {};
  if (!(dt_s > 0)) throw std::invalid_argument("trajectory: dt_s must be positive");
  const double t0 = keyframes.front().t_s, t1 = keyframes.back().t_s;
  // A last sample closer than this to the final keyframe is taken as the final keyframe itself, so
  // rounding in t0 + k dt never adds a sliver step.
  const double snap = 1e-6 * dt_s;
  std::vector<double> t;
  for (long k = 0;; ++k) {
    const double tk = t0 + static_cast<double>(k) * dt_s;
    if (tk >= t1 - snap) break;
    t.push_back(tk);
  }
  t.push_back(t1);
  return t;
}

std::vector<Pose> sample_trajectory(const std::vector<Keyframe>& keyframes, double dt_s) {
  std::vector<Pose> out;
  std::size_t seg = 0;
  for (const double t : trajectory_times(keyframes, dt_s)) {
    while (seg + 2 < keyframes.size() && t > keyframes[seg + 1].t_s) ++seg;
    if (keyframes.size() == 1) {
      out.push_back(make_pose(keyframes[0].p_EI, keyframes[0].q_EI));
      continue;
    }
    const Keyframe& a = keyframes[seg];
    const Keyframe& b = keyframes[seg + 1];
    const double span = b.t_s - a.t_s;
    const double alpha = span > 0 ? std::clamp((t - a.t_s) / span, 0.0, 1.0) : 1.0;
    const Vec3 p = (1 - alpha) * a.p_EI + alpha * b.p_EI;
    out.push_back(make_pose(p, a.q_EI.slerp(alpha, b.q_EI)));
  }
  return out;
}

IndenterSpec parse_indenter_spec(const nlohmann::json& j, const std::string& where, const std::string& ptr,
                                 const std::string& data_root, const std::string& base_dir) {
  jsonin::reject_unknown_keys(j,
                              {"shape", "radius_m", "minor_radius_m", "length_m", "fillet_m", "size_m", "mesh", "scale",
                               "allow_open", "sample_spacing_m", "analytic_sdf"},
                              where, ptr);
  IndenterSpec s;
  if (auto* v = jsonin::find(j, "shape")) s.shape = jsonin::string(*v, where, child(ptr, "shape"));
  if (s.shape.empty() && jsonin::find(j, "mesh")) s.shape = "mesh";
  if (s.shape != "sphere" && s.shape != "torus" && s.shape != "cylinder" && s.shape != "box" && s.shape != "mesh")
    jsonin::fail(where, child(ptr, "shape"),
                 "unknown shape '" + s.shape + "' (expected sphere, torus, cylinder, box or mesh)");
  auto positive = [&](const char* key, double* out) {
    if (auto* v = jsonin::find(j, key)) *out = jsonin::positive_number(*v, where, child(ptr, key));
  };
  positive("radius_m", &s.radius_m);
  positive("minor_radius_m", &s.minor_radius_m);
  positive("length_m", &s.length_m);
  positive("scale", &s.scale);
  positive("sample_spacing_m", &s.sample_spacing_m);
  if (auto* v = jsonin::find(j, "fillet_m")) {
    s.fillet_m = jsonin::finite_number(*v, where, child(ptr, "fillet_m"));
    if (s.fillet_m < 0) jsonin::fail(where, child(ptr, "fillet_m"), "must be >= 0");
  }
  if (auto* v = jsonin::find(j, "size_m")) {
    s.size_m = jsonin::vec3(*v, where, child(ptr, "size_m"));
    if (!(s.size_m.array() > 0).all()) jsonin::fail(where, child(ptr, "size_m"), "expected 3 positive numbers");
  }
  if (auto* v = jsonin::find(j, "allow_open")) s.allow_open = jsonin::boolean(*v, where, child(ptr, "allow_open"));
  if (auto* v = jsonin::find(j, "analytic_sdf"))
    s.analytic_sdf = jsonin::boolean(*v, where, child(ptr, "analytic_sdf"));
  if (s.shape == "torus" && !(s.minor_radius_m < s.radius_m))
    jsonin::fail(where, child(ptr, "minor_radius_m"), "must be smaller than radius_m (the major radius)");
  if (s.shape == "mesh") {
    const std::string given = jsonin::string(jsonin::member(j, "mesh", where, ptr), where, child(ptr, "mesh"));
    s.mesh_path = resolve_at(given, data_root, base_dir, where, child(ptr, "mesh"));
    if (!fs::exists(s.mesh_path))
      jsonin::fail(where, child(ptr, "mesh"),
                   "mesh file '" + s.mesh_path + "' not found (data root: " + data_root + ")");
  }
  return s;
}

std::shared_ptr<const Sensor> parse_scene_sensor(const nlohmann::json& j, const std::string& where,
                                                 const std::string& data_root, const std::string& base_dir) {
  const std::string ptr = "/sensor";
  jsonin::reject_unknown_keys(j, {"gel", "markers", "camera", "markers_depth_m"}, where, ptr);
  Camera camera;
  if (auto* c = jsonin::find(j, "camera")) {
    const std::string cptr = child(ptr, "camera");
    jsonin::reject_unknown_keys(
        *c, {"model", "mm_per_px", "principal_px", "image_size_px", "focal_px", "distance_m", "k1"}, where, cptr);
    parse_camera_model(*c, where, cptr, &camera);
    if (auto* v = jsonin::find(*c, "mm_per_px"))
      camera.mm_per_px = jsonin::positive_number(*v, where, child(cptr, "mm_per_px"));
    if (auto* v = jsonin::find(*c, "principal_px"))
      camera.principal_px = jsonin::vec2(*v, where, child(cptr, "principal_px"));
    if (auto* v = jsonin::find(*c, "image_size_px")) {
      const Vec2 size = jsonin::vec2(*v, where, child(cptr, "image_size_px"));
      if (size.x() < 1 || size.y() < 1 || size != size.array().round().matrix())
        jsonin::fail(where, child(cptr, "image_size_px"), "expected two positive integers");
      camera.width_px = static_cast<int>(size.x());
      camera.height_px = static_cast<int>(size.y());
    }
  }
  std::vector<Vec2> markers;
  if (auto* m = jsonin::find(j, "markers")) {
    const std::string mptr = child(ptr, "markers");
    if (m->is_string()) {
      markers = marker_grid_px(parse_marker_grid(m->get<std::string>(), where + ": " + mptr), camera);
    } else if (m->is_array() && !m->empty()) {
      for (std::size_t i = 0; i < m->size(); ++i) markers.push_back(jsonin::vec2((*m)[i], where, child(mptr, i)));
    } else {
      jsonin::fail(where, mptr, "expected a grid such as \"7x9\" or an array of [u, v] pixel positions");
    }
  } else {
    markers = marker_grid_px(MarkerGrid{}, camera);
  }
  GelSpec gel;
  const auto* g = jsonin::find(j, "gel");
  if (g && g->is_object()) {  // {"surface": "spherical_cap", "radius_m", "footprint_radius_m", "thickness_m"}
    const std::string gptr = child(ptr, "gel");
    jsonin::reject_unknown_keys(*g, {"surface", "radius_m", "footprint_radius_m", "thickness_m"}, where, gptr);
    gel.surface = jsonin::string(jsonin::member(*g, "surface", where, gptr), where, child(gptr, "surface"));
    if (gel.surface != "spherical_cap")
      jsonin::fail(where, child(gptr, "surface"),
                   "a gel object describes a spherical_cap (give \"flat\" or a mesh path as a string)");
    gel.thickness_m =
        jsonin::positive_number(jsonin::member(*g, "thickness_m", where, gptr), where, child(gptr, "thickness_m"));
    parse_spherical_cap(*g, where, gptr, &gel);
  }
  if (auto* v = jsonin::find(j, "markers_depth_m"))
    gel.markers_depth_m = parse_markers_depth(*v, gel, where, child(ptr, "markers_depth_m"));
  if (g && !g->is_object()) {
    const std::string text = jsonin::string(*g, where, child(ptr, "gel"));
    if (camera.pinhole() && text != "flat")
      jsonin::fail(where, child(ptr, "gel"), "a pinhole camera needs a flat or spherical_cap gel, not a mesh file");
    if (text != "flat") {
      const std::string path = resolve_at(text, data_root, base_dir, where, child(ptr, "gel"));
      if (!fs::exists(path))
        jsonin::fail(where, child(ptr, "gel"), "gel mesh '" + path + "' not found (data root: " + data_root + ")");
      gel.surface = path;
      const TriMesh mesh_E = gelsight_mini_gel_in_E(path);
      return std::make_shared<const Sensor>(make_sensor(camera, gel, markers, &mesh_E));
    }
  }
  return std::make_shared<const Sensor>(make_sensor(camera, gel, markers));
}

namespace {

std::vector<Keyframe> parse_keyframes(const nlohmann::json& ks, const std::string& where, const std::string& ptr) {
  if (!ks.is_array() || ks.empty()) jsonin::fail(where, ptr, "expected a non-empty array of keyframes");
  std::vector<Keyframe> out;
  for (std::size_t i = 0; i < ks.size(); ++i) {
    const std::string kptr = child(ptr, i);
    jsonin::reject_unknown_keys(ks[i], {"t_s", "xyz_m", "rpy_deg"}, where, kptr);
    Keyframe k;
    k.t_s = jsonin::finite_number(jsonin::member(ks[i], "t_s", where, kptr), where, child(kptr, "t_s"));
    if (!out.empty() && !(k.t_s > out.back().t_s))
      jsonin::fail(where, child(kptr, "t_s"), "keyframe times must increase");
    const Vec3 xyz = jsonin::vec3(jsonin::member(ks[i], "xyz_m", where, kptr), where, child(kptr, "xyz_m"));
    Vec3 rpy = Vec3::Zero();
    if (auto* v = jsonin::find(ks[i], "rpy_deg")) rpy = jsonin::vec3(*v, where, child(kptr, "rpy_deg"));
    const Pose X = rpy_pose(xyz, rpy);
    k.p_EI = X.translation();
    k.q_EI = Quat(X.linear());
    out.push_back(k);
  }
  return out;
}

void parse_dataset_replay(const nlohmann::json& d, const std::string& where, const std::string& data_root,
                          const std::string& base_dir, bool scene_has_indenter, Scene* scene) {
  const std::string ptr = "/dataset";
  jsonin::reject_unknown_keys(d, {"path", "sample"}, where, ptr);
  const std::string given = jsonin::string(jsonin::member(d, "path", where, ptr), where, child(ptr, "path"));
  const std::string dir = resolve_at(given, data_root, base_dir, where, child(ptr, "path"));
  if (!fs::is_directory(dir))
    jsonin::fail(where, child(ptr, "path"), "dataset folder '" + dir + "' not found (data root: " + data_root + ")");
  const std::string id = jsonin::string(jsonin::member(d, "sample", where, ptr), where, child(ptr, "sample"));
  const Dataset ds = read_dataset(dir);
  bool found = false;
  for (const auto& s : ds.samples) found = found || s.id == id;
  if (!found) jsonin::fail(where, child(ptr, "sample"), "no sample '" + id + "' in " + dir);
  const TsdSampleInfo& info = ds.sample(id);
  const SampleData data = read_sample(ds, id);
  scene->dataset_dir = dir;
  scene->sample_id = id;
  scene->motion = info.motion;
  scene->dt_s = info.dt_s;
  scene->X_EI = data.poses();
  scene->t_s = data.t_s;
  if (!scene_has_indenter) {
    scene->indenter_spec = IndenterSpec{};
    scene->indenter_spec.shape = "mesh";
    scene->indenter_spec.mesh_path = ds.mesh_path(info.indenter);
  }
  scene->sensor_model = ds.sensor_model;
  if (!gel_surface_is_mesh(ds.gel.surface)) {
    scene->sensor = std::make_shared<const Sensor>(make_sensor(ds.camera, ds.gel, ds.markers_rest_px));
  } else {
    GelSpec gel = ds.gel;
    gel.surface = (fs::path(dir) / ds.gel.surface).string();
    const TriMesh mesh_E = gelsight_mini_gel_in_E(gel.surface);
    scene->sensor = std::make_shared<const Sensor>(make_sensor(ds.camera, gel, ds.markers_rest_px, &mesh_E));
  }
}

}  // namespace

Scene parse_scene(const nlohmann::json& j, const std::string& where, const std::string& data_root,
                  const std::string& base_dir) {
  jsonin::reject_unknown_keys(
      j, {"name", "motion", "sensor", "indenter", "params", "trajectory", "dataset", "description"}, where, "");
  Scene scene;
  scene.path = where;
  scene.name = fs::path(where).stem().string();
  if (auto* v = jsonin::find(j, "name")) scene.name = jsonin::string(*v, where, "/name");
  if (auto* v = jsonin::find(j, "motion")) {
    scene.motion = jsonin::string(*v, where, "/motion");
    if (!is_tsd_motion(scene.motion))
      jsonin::fail(where, "/motion",
                   "unknown motion '" + scene.motion + "' (expected dilation, shear, twist, roll, slip or free)");
  }
  if (auto* p = jsonin::find(j, "params")) {
    jsonin::require_object(*p, where, "/params");
    for (const auto& [model, table] : p->items()) {
      // Values are checked against each model's ParamSet when the model is made.
      jsonin::require_object(table, where, child("/params", model));
      scene.params[model] = table;
    }
  }
  const auto* trajectory = jsonin::find(j, "trajectory");
  const auto* dataset = jsonin::find(j, "dataset");
  if ((trajectory != nullptr) == (dataset != nullptr))
    jsonin::fail(where, "", "a scene needs exactly one of \"trajectory\" and \"dataset\"");
  const auto* indenter = jsonin::find(j, "indenter");
  if (indenter)
    scene.indenter_spec = parse_indenter_spec(*indenter, where, "/indenter", data_root, base_dir);
  else if (trajectory)
    jsonin::fail(where, "/indenter", "missing");

  if (trajectory) {
    const std::string ptr = "/trajectory";
    jsonin::reject_unknown_keys(*trajectory, {"dt_s", "substeps", "keyframes"}, where, ptr);
    if (auto* v = jsonin::find(*trajectory, "dt_s"))
      scene.dt_s = jsonin::positive_number(*v, where, child(ptr, "dt_s"));
    if (auto* v = jsonin::find(*trajectory, "substeps")) {
      scene.substeps = jsonin::integer(*v, where, child(ptr, "substeps"));
      if (scene.substeps < 1) jsonin::fail(where, child(ptr, "substeps"), "must be >= 1");
    }
    scene.keyframes =
        parse_keyframes(jsonin::member(*trajectory, "keyframes", where, ptr), where, child(ptr, "keyframes"));
    scene.X_EI = sample_trajectory(scene.keyframes, scene.dt_s);
    scene.t_s = trajectory_times(scene.keyframes, scene.dt_s);
    if (auto* s = jsonin::find(j, "sensor"))
      scene.sensor = parse_scene_sensor(*s, where, data_root, base_dir);
    else
      scene.sensor = std::make_shared<const Sensor>(make_default_sensor());
  } else {
    if (jsonin::find(j, "sensor")) jsonin::fail(where, "/sensor", "a dataset replay takes its sensor from the dataset");
    parse_dataset_replay(*dataset, where, data_root, base_dir, indenter != nullptr, &scene);
  }
  return scene;
}

Scene load_scene(const std::string& path, const std::string& data_root) {
  const nlohmann::json j = jsonin::load_file(path);
  return parse_scene(j, path, data_root, fs::path(path).parent_path().string());
}

}  // namespace sb
