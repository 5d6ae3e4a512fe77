#include "app/session.hpp"

#include "app/command.hpp"
#include "core/calibration/param_sets.hpp"
#include "core/effects/model_spec.hpp"
#include "core/models/model_family.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <regex>

#include "core/base/data_root.hpp"
#include "core/base/display_path.hpp"
#include "core/base/error.hpp"
#include "core/base/format.hpp"
#include "core/base/install_paths.hpp"
#include "core/base/strings.hpp"
#include "core/calibration/metrics.hpp"
#include "core/data/json_read.hpp"
#include "core/data/tsd.hpp"
#include "core/loop/loop_answer.hpp"
#include "core/loop/residual.hpp"
#include "core/loop/residual_view.hpp"
#include "core/models/model.hpp"
#include "core/workbench/report_dataset.hpp"

namespace sb::app {

namespace fs = std::filesystem;

std::string default_scene_path() {
  const fs::path p = fs::path(home_dir()) / "scenes" / "default.json";
  return fs::exists(p) ? p.string() : std::string();
}

Scene builtin_default_scene() {
  Scene s;
  s.name = "default (built in): 4 mm sphere, press 1 mm, slide 3 mm";
  s.sensor = std::make_shared<const Sensor>(make_default_sensor());
  s.indenter_spec.shape = "sphere";
  s.indenter_spec.radius_m = 0.004;
  s.dt_s = 0.02;
  // Sphere centre 0.5 mm above the gel, pressed to 1 mm depth in 0.4 s, held, slid 3 mm in 1 s, held.
  const double r = 0.004;
  s.keyframes = {{0.0, Vec3(0, 0, r + 0.5e-3), Quat::Identity()},
                 {0.4, Vec3(0, 0, r - 1.0e-3), Quat::Identity()},
                 {0.5, Vec3(0, 0, r - 1.0e-3), Quat::Identity()},
                 {1.5, Vec3(3.0e-3, 0, r - 1.0e-3), Quat::Identity()},
                 {1.7, Vec3(3.0e-3, 0, r - 1.0e-3), Quat::Identity()}};
  s.X_EI = sample_trajectory(s.keyframes, s.dt_s);
  return s;
}

namespace {

// HydroShear or one of its model-form variants, as its family's descriptor lists them, optionally with effects
// (the loop's answer, "hydroshear+dome_sway+..."); throws InputError for anything else.
void check_beside_hydroshear(const std::string& beside) {
  const std::vector<std::string> family = model_family("hydroshear").form_ids();
  const auto form_of = [](const std::string& id) -> std::string {
    try {
      return parse_model_spec(id).form;
    } catch (const std::exception&) {
      return {};  // not a model id at all: the message below names the choices
    }
  };
  if (std::find(family.begin(), family.end(), form_of(beside)) != family.end()) return;
  std::string names;
  for (const auto& id : family) names += (names.empty() ? "" : ", ") + id;
  throw InputError("--beside-hydroshear", "expected auto, none or one of " + names +
                                              " (optionally with effects: hydroshear+lens_distortion), got '" + beside +
                                              "'");
}

// "auto": the loop's answer for the sensor of a real recording when it has one, else the variant the loop selects
// on the twin sets when the set holds fitted values for it.
std::string auto_beside(const NamedParamSet& param_set, const LoopAnswer* answer) {
  if (answer != nullptr) return answer->summary.after_model;
  return param_set.tables.count(kBesideHydroshearAutoModel) != 0 ? kBesideHydroshearAutoModel : "";
}

// Each model starts from the session's parameter set (the loop's answer: the loop's own fit), then the scene's table.
std::vector<std::unique_ptr<ShearModel>> make_models(const Scene& scene, const SessionOptions& o,
                                                     const NamedParamSet& param_set, const LoopAnswer* answer,
                                                     const std::shared_ptr<const Indenter>& indenter) {
  std::vector<std::unique_ptr<ShearModel>> models;
  std::vector<std::string> ids;
  for (const ModelFamily& f : model_families()) ids.push_back(o.open.form_shown(f.id));
  std::string beside = o.open.beside_hydroshear;
  if (beside == kBesideHydroshearAuto) beside = auto_beside(param_set, answer);
  if (!beside.empty()) {
    check_beside_hydroshear(beside);
    ids.insert(ids.begin() + 1, beside);
  }
  for (const std::string& id : ids) {
    auto m = make_spec_model(id, scene.sensor, indenter);
    m->set_params(param_set.params(id));
    if (answer != nullptr && id == answer->summary.after_model) {
      ParamSet p = m->params();
      p.update_from_json(answer->summary.after_params, answer->summary.file + ": /after/params");
      m->set_params(p);
    }
    if (auto it = scene.params.find(id); it != scene.params.end()) {
      ParamSet p = m->params();
      p.update_from_json(it->second, scene.path.empty() ? "scene" : scene.path);
      m->set_params(p);
    }
    models.push_back(std::move(m));
  }
  return models;
}

// A multi-sensor log (dataset.json "shearbench": {"sensors": [sample ids]}, e.g. examples/mujoco_grasp's two pads,
// every sample at the same frames): the replayed sample's panel and each other sensor's are named by sample id.
void load_beside(const Dataset& ds, const std::string& replayed, Warnings* warnings, ui::MeasuredData* measured) {
  const auto sb_it = ds.extra.find("shearbench");
  if (sb_it == ds.extra.end() || !sb_it->is_object() || !sb_it->contains("sensors")) return;
  const nlohmann::json& sensors = (*sb_it)["sensors"];
  if (!sensors.is_array()) throw InputError(ds.json_path(), "/shearbench/sensors: expected an array of sample ids");
  bool listed = false;
  for (const auto& id : sensors) listed = listed || (id.is_string() && id.get<std::string>() == replayed);
  if (!listed) return;
  measured->label = replayed + " (logged)";
  for (const auto& id : sensors) {
    if (!id.is_string()) throw InputError(ds.json_path(), "/shearbench/sensors: expected sample ids (strings)");
    if (id.get<std::string>() == replayed) continue;
    SampleData other = read_sample(ds, id.get<std::string>(), warnings);
    measured->beside.push_back({id.get<std::string>() + " (logged)", std::move(other.markers_px)});
  }
}

// The measured side of a dataset replay: marker field and frames of each step, the sample list.
void load_measured(Session& s, const std::string& data_root) {
  Warnings warnings;
  const Dataset ds = read_dataset(s.scene.dataset_dir, &warnings);
  SampleData data = read_sample(ds, s.scene.sample_id, &warnings);
  const TsdSampleInfo& info = ds.sample(s.scene.sample_id);
  s.measured.poses = data.poses();
  s.measured.disp_px = std::move(data.markers_px);
  s.measured.frame_paths = std::move(data.frame_paths);
  s.measured.label = ds.kind == "real" ? "Measured" : "Measured (twin)";
  load_beside(ds, info.id, &warnings, &s.measured);
  // "data:twin/..." when under the data root, relative when under the working folder: not this machine's paths.
  s.replay.dataset_dir = display_path(s.scene.dataset_dir, data_root);
  s.replay.samples.clear();
  for (const auto& smp : ds.samples) s.replay.samples.push_back(smp.id);
  s.replay.sample_index =
      static_cast<int>(std::find(s.replay.samples.begin(), s.replay.samples.end(), info.id) - s.replay.samples.begin());
  s.title = ds.name + " / " + info.id + "  (" + info.motion + ", " + info.split + ", " + ds.kind + ")";
  // How many markers the sample's last frame tracked: a sample with none is said in words, not drawn as 0.00 px.
  s.replay.total_markers = static_cast<int>(s.scene.sensor->markers_rest_px.size());
  s.replay.tracked_markers = 0;
  if (!s.measured.disp_px.empty())
    for (const Vec2& d : s.measured.disp_px.back()) s.replay.tracked_markers += d.allFinite();
  if (s.replay.tracked_markers == 0) s.title += "  [no marker tracked]";
}

// The data root's raw/ holds real recordings (imported by `shearbench import`), twin/ finite-element references;
// a set fitted on a dataset elsewhere says which it is in its dataset.json.
bool fitted_on_real_recording(const NamedParamSet& set, const std::string& data_root) {
  const auto it = set.provenance.find("dataset");
  if (it == set.provenance.end() || !it->is_string()) return false;
  const std::string fitted_on = it->get<std::string>();
  if (fitted_on.rfind("data:raw/", 0) == 0) return true;
  try {
    return read_dataset(resolve_user_path(fitted_on, data_root, fs::current_path().string())).kind == "real";
  } catch (const std::exception&) {
    return false;  // not on this machine: nothing says it is a real recording
  }
}

// A real recording's sensor has a loop answer when the loop ran on the real set its parameter set was fitted on. A
// twin set is a finite-element reference of no sensor (its runs' answers stay in their reports), and a scene has
// no measured field to hold an answer against.
std::optional<LoopAnswer> loop_answer_for(const Session& s, const std::string& data_root) {
  if (s.scene.dataset_dir.empty() || read_dataset(s.scene.dataset_dir).kind != "real") return std::nullopt;
  if (!fitted_on_real_recording(s.param_set, data_root)) return std::nullopt;
  std::string skipped;
  std::optional<LoopAnswer> answer = find_shipped_loop_answer(s.param_set, &skipped);
  if (!skipped.empty()) std::fprintf(stderr, "warning: residual reports skipped: %s\n", skipped.c_str());
  return answer;
}

}  // namespace

void open_report_dataset(SessionSource& open, const std::string& residual_file, const std::string& data_root_flag) {
  if (residual_file.empty() || !open.dataset_dir.empty() || !open.scene_path.empty()) return;
  const std::string dir =
      report_dataset_path(load_residual_summary(residual_file).dataset, resolve_data_root(data_root_flag));
  if (!dir.empty()) open.dataset_dir = dir;
}

Session open_session(const SessionOptions& o) {
  Session s;
  // A named set is read before anything else (a bad name is the first error); none named: the default for
  // the scene's sensor, once the scene is read.
  if (!o.open.param_set.empty()) s.param_set = load_param_set(o.open.param_set);
  const std::string root = resolve_data_root(o.data_root);
  double indenter_bottom_shift = 0;
  if (!o.open.dataset_dir.empty()) {
    // A dataset replay is a scene with a "dataset" entry: the scene parser builds sensor, indenter, path.
    // As typed: data:..., else the working folder, else the data root ("twin/twin_sphere35" typed in the workbench).
    const std::string dir = resolve_user_path(o.open.dataset_dir, root, fs::current_path().string());
    std::string sample = o.open.sample_id;
    if (sample.empty()) {
      const Dataset ds = read_dataset(dir);
      if (ds.samples.empty()) throw InputError(ds.json_path(), "the dataset lists no samples");
      sample = ds.samples.front().id;
    }
    const nlohmann::json j = {{"name", fs::path(dir).filename().string() + " / " + sample},
                              {"dataset", {{"path", dir}, {"sample", sample}}}};
    s.scene = parse_scene(j, "--dataset " + o.open.dataset_dir, root, fs::current_path().string());
  } else if (!o.open.scene_path.empty()) {
    s.scene = load_scene(resolve_user_path(o.open.scene_path, root, fs::current_path().string()), root);
  } else if (const std::string def = default_scene_path(); !def.empty()) {
    s.scene = load_scene(def, root);
  } else {
    s.scene = builtin_default_scene();
  }
  if (!o.open.indenter_mesh.empty()) {
    // The mesh's lowest point is put where the scene's indenter had its lowest point, so the same path
    // presses it in by the same depth.
    const double old_bottom = s.scene.indenter_spec.shape == "sphere" ? -s.scene.indenter_spec.radius_m : 0.0;
    s.scene.indenter_spec = IndenterSpec{};
    s.scene.indenter_spec.shape = "mesh";
    s.scene.indenter_spec.mesh_path = o.open.indenter_mesh;
    s.scene.indenter_spec.scale = o.open.indenter_scale;
    s.scene.indenter_spec.allow_open = true;
    s.scene.name += " [indenter: " + o.open.indenter_mesh + "]";
    indenter_bottom_shift = old_bottom;
  }
  if (o.open.param_set.empty()) s.param_set = load_param_set(default_param_set_for(s.scene.sensor_model));
  const std::string base_dir = s.scene.path.empty() ? std::string() : fs::path(s.scene.path).parent_path().string();
  Warnings warnings;
  auto indenter = std::make_shared<const Indenter>(build_indenter(s.scene.indenter_spec, root, base_dir, &warnings));
  if (!o.open.indenter_mesh.empty()) {
    const double shift = indenter_bottom_shift - indenter->mesh.bounds().min().z();
    for (Pose& X : s.scene.X_EI) X.translation().z() += shift;
  }
  const std::optional<LoopAnswer> answer = loop_answer_for(s, root);
  if (answer) s.loop_answer_model = answer->summary.after_model;
  if (answer && o.open.beside_hydroshear == kBesideHydroshearAuto)
    s.beside_note = "beside HydroShear: the loop's answer for this sensor, " + answer->summary.answer_labelled + " (" +
                    format_number(answer->summary.before_rmse_px, "%.3g") + " -> " +
                    format_number(answer->summary.after_rmse_px, "%.3g") + " px on its validation split, " +
                    display_path(answer->summary.file, root) + ")";
  s.state = std::make_unique<AppState>(s.scene.sensor, indenter,
                                       make_models(s.scene, o, s.param_set, answer ? &*answer : nullptr, indenter),
                                       s.scene.X_EI, s.scene.dt_s);
  if (!s.scene.dataset_dir.empty()) load_measured(s, root);
  if (s.title.empty())
    s.title = s.scene.name.empty() ? (s.scene.path.empty() ? std::string("scene") : display_path(s.scene.path, root))
                                   : s.scene.name;
  return s;
}

ui::MetricsFn field_metrics() {
  return [](const std::vector<Vec2>& sim, const std::vector<Vec2>& measured) -> std::optional<ui::FieldMetrics> {
    if (sim.size() != measured.size()) return std::nullopt;
    const MetricsResult r = frame_metrics(sim, measured);
    // A frame where nothing measured moves is not counted (core/calibration/metrics.hpp): no readout then.
    if (r.n == 0) return std::nullopt;
    return ui::FieldMetrics{r.rmse_px, r.n_cs > 0 ? r.cs : std::nan("")};
  };
}

void load_params_file(AppState& state, const std::string& path) {
  const nlohmann::json j = jsonin::load_file(path);  // the same reader as the CLI's (fuzzed)
  if (!j.is_object()) throw InputError(path, "expected an object {model id: {name: value}}");
  const AppSnapshot snap = state.snapshot();
  for (std::size_t m = 0; m < snap.models.size(); ++m) {
    if (!j.contains(snap.models[m].id)) continue;
    ParamSet p = snap.models[m].params;
    p.update_from_json(j[snap.models[m].id], path + ": /" + snap.models[m].id);
    state.request_params(m, p);
  }
}

void save_params_file(const AppSnapshot& snap, const std::string& path) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& m : snap.models) j[m.id] = m.params.to_json();
  write_file_atomic(path, j.dump(2) + "\n");
}

std::pair<int, int> parse_size(const std::string& text) {
  static const std::regex re(R"((\d{2,5})x(\d{2,5}))");
  std::smatch m;
  if (!std::regex_match(text, m, re))
    throw InputError("--size", "expected WIDTHxHEIGHT such as 1600x900, got '" + text + "'");
  return {std::stoi(m[1]), std::stoi(m[2])};
}

void add_source_options(CLI::App& sub, SessionSource& open) {
  sub.add_option("--scene", open.scene_path, "scene JSON (default: scenes/default.json)");
  sub.add_option("--dataset", open.dataset_dir, "replay a tsd/1 dataset folder");
  sub.add_option("--sample", open.sample_id, "sample id of the dataset (default: the first)");
  sub.add_option("--indenter-mesh", open.indenter_mesh, "replace the indenter by a mesh (e.g. data:meshes/cow.obj)");
  sub.add_option("--indenter-scale", open.indenter_scale, "mesh units to metres")->capture_default_str();
  for (const ModelFamily& f : model_families())  // --hydroshear hydroshear | hydroshear-layer | ...
    sub.add_option("--" + f.id, open.form_shown(f.id), join(f.form_ids(), " | "))->capture_default_str();
  sub.add_option("--beside-hydroshear", open.beside_hydroshear,
                 "a HydroShear variant in a panel of its own beside HydroShear's, none, or auto: the variant the "
                 "residual loop selects on the twin sets (hydroshear-contact) when the parameter set holds fitted "
                 "values for it")
      ->capture_default_str()
      ->transform(CLI::Validator(  // a transform: CLI11's checks see a copy, its transforms the value
          [](std::string& v) {
            if (v == "none") v.clear();
            return std::string();
          },
          "ID|auto|none"));
  add_param_set_flag(sub, open.param_set);
}

std::vector<std::string> source_arguments(const SessionSource& open) {
  std::vector<std::string> args;
  for (const ModelFamily& f : model_families()) args.insert(args.end(), {"--" + f.id, open.form_shown(f.id)});
  const auto add = [&](const char* flag, const std::string& value) {
    if (!value.empty()) args.insert(args.end(), {flag, value});
  };
  add("--param-set", open.param_set);
  add("--scene", open.scene_path);
  add("--dataset", open.dataset_dir);
  add("--sample", open.sample_id);
  args.insert(args.end(), {"--beside-hydroshear", open.beside_hydroshear.empty() ? "none" : open.beside_hydroshear});
  if (!open.indenter_mesh.empty())
    args.insert(args.end(),
                {"--indenter-mesh", open.indenter_mesh, "--indenter-scale", std::to_string(open.indenter_scale)});
  return args;
}

}  // namespace sb::app
