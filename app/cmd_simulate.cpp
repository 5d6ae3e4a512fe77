// `shearbench simulate --scene S.json --model M [--params P.json] --out DIR [--force]`: runs one shear model over a
// scene's indenter poses and writes the predicted marker field as a tsd/1 dataset (one sample, the
// scene's poses, the indenter mesh under meshes/, provenance naming model, parameters and scene).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>

#include <unistd.h>

#include "app/command.hpp"
#include "core/api/sensor_model_impl.hpp"
#include "core/base/data_root.hpp"
#include "core/base/reproducible.hpp"
#include "core/calibration/evaluate.hpp"
#include "core/calibration/param_sets.hpp"
#include "core/calibration/prediction_export.hpp"
#include "core/data/json_read.hpp"
#include "core/data/scene.hpp"
#include "core/geometry/mesh.hpp"
#include "core/models/model.hpp"

namespace fs = std::filesystem;

namespace sb::app {
namespace {

struct SimulateArgs {
  std::string scene;
  std::string model;
  std::string params;
  std::string param_set;  // empty: the default for the scene's sensor
  std::string out;
  bool force = false;
};

// Refuses --out when it is a file, or a folder that holds anything, unless --force: a simulation never
// writes over a user's earlier dataset by accident. Called before any work.
void check_out_folder(const SimulateArgs& a) {
  std::error_code ec;
  if (!fs::exists(a.out, ec)) return;
  if (!fs::is_directory(a.out, ec)) throw InputError(a.out, "--out names a file, not a folder");
  if (a.force || fs::is_empty(a.out, ec)) return;
  throw InputError(a.out, "--out already holds files; simulate does not write over them (--force replaces the folder)");
}

// The dataset written to --out. Over a folder that holds files (--force), it is written whole into a hidden
// sibling first, and only then takes the folder's place: a failed or killed run leaves the old dataset.
void write_out_folder(const std::string& out, const PredictionExport& e) {
  std::error_code ec;
  if (!fs::exists(out, ec) || fs::is_empty(out, ec)) {
    write_prediction_dataset(out, e);
    return;
  }
  const fs::path target = fs::absolute(out).lexically_normal();
  const fs::path name = target.has_filename() ? target.filename() : target.parent_path().filename();
  const fs::path folder = target.has_filename() ? target : target.parent_path();
  const std::string suffix = ".tmp." + std::to_string(::getpid());
  const fs::path fresh = folder.parent_path() / ("." + name.string() + suffix);
  const fs::path old = folder.parent_path() / ("." + name.string() + ".old" + suffix);
  fs::remove_all(fresh, ec);
  write_prediction_dataset(fresh.string(), e);
  fs::rename(folder, old);
  fs::rename(fresh, folder);
  fs::remove_all(old, ec);
}

int run_simulate(const SimulateArgs& a, const GlobalOptions& g) {
  require_model(a.model);
  check_out_folder(a);
  const std::string root = resolve_data_root(g.data_root_flag);
  const Scene scene = load_scene(a.scene, root);
  Warnings warnings;
  auto indenter = std::make_shared<Indenter>(
      build_indenter(scene.indenter_spec, root, fs::path(a.scene).parent_path().string(), &warnings));
  if (indenter->name.empty()) indenter->name = "indenter";

  // Parameters: the set (default: the one for the scene's sensor), then the scene's table, then --params.
  const NamedParamSet set = load_param_set(param_set_or_default(a.param_set, scene.sensor_model));
  if (const std::string w = sensor_mismatch(set, scene.sensor_model); !w.empty()) warnings.add(w);
  ParamSet params = set.params(a.model);
  if (const auto it = scene.params.find(a.model); it != scene.params.end())
    params.update_from_json(it->second, a.scene + ": /params/" + a.model);
  if (!a.params.empty())
    params.update_from_json(params_for_model(jsonin::load_file(a.params), a.model, true, a.params), a.params);
  // Through the public API (one env), as a consumer of libshearbench steps it; the Pose-typed step keeps the
  // scene's sampled poses exactly.
  shearbench::SensorModel api = shearbench::SensorModel::Impl::make(a.model, scene.sensor, indenter, params, 1);
  shearbench::SensorModel::Impl& model = api.impl();

  const auto start = std::chrono::steady_clock::now();
  PredictionExport e;
  std::vector<Vec2> out(scene.sensor->p_EM.size());
  const double sub_dt = scene.dt_s / scene.substeps;
  for (std::size_t k = 0; k < scene.X_EI.size(); ++k) {
    // Sub-steps interpolate the pose between samples (frame 0 starts at rest, no sub-steps).
    if (k > 0 && scene.substeps > 1) {
      const Pose& A = scene.X_EI[k - 1];
      const Pose& B = scene.X_EI[k];
      const Quat qa(A.linear()), qb(B.linear());
      for (int s = 1; s < scene.substeps; ++s) {
        const double alpha = static_cast<double>(s) / scene.substeps;
        const Pose X = make_pose((1 - alpha) * A.translation() + alpha * B.translation(), qa.slerp(alpha, qb));
        model.step_poses({&X, 1}, sub_dt, out);
      }
    }
    model.step_poses({&scene.X_EI[k], 1}, scene.substeps > 1 && k > 0 ? sub_dt : scene.dt_s, out);
    e.t_s.push_back(scene.t_s.empty() ? static_cast<double>(k) * scene.dt_s : scene.t_s[k]);
    e.X_EI.push_back(scene.X_EI[k]);
    e.disp_px.push_back(out);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  const nlohmann::json pj = params.to_json();
  e.name = scene.name + "_" + a.model;
  e.provenance =
      "shearbench " SHEARBENCH_VERSION " simulate: model " + a.model + ", params " + pj.dump() + ", scene " + a.scene +
      (scene.dataset_dir.empty() ? "" : " (replaying " + scene.dataset_dir + " sample " + scene.sample_id + ")");
  e.shearbench = {{"model", a.model}, {"params", pj}, {"scene", a.scene}};
  if (timings_in_outputs()) e.shearbench["seconds"] = seconds;
  e.sample_id = scene.sample_id.empty() ? scene.name : scene.sample_id;
  e.motion = scene.motion;
  e.sensor = scene.sensor;
  e.indenter = indenter;
  e.dt_s = scene.dt_s;
  write_out_folder(a.out, e);
  if (!g.quiet) {
    for (const auto& w : warnings.messages) std::fprintf(stderr, "warning: %s\n", w.c_str());
    std::printf("%s on %s: %zu frames in %.3g ms (%.3g ms/frame) -> %s\n", a.model.c_str(), scene.name.c_str(),
                scene.X_EI.size(), 1e3 * seconds, 1e3 * seconds / std::max<std::size_t>(1, scene.X_EI.size()),
                a.out.c_str());
  }
  return 0;
}

void add_flags(CLI::App& sub, SimulateArgs& a) {
  sub.add_option("--scene", a.scene, "scene JSON (scenes/*.json)")->required();
  sub.add_option("--model", a.model,
                 model_ids_text() + ", or a form with effects (hydroshear-contact+viscoelastic_creep)")
      ->required();
  add_param_set_flag(sub, a.param_set);
  add_params_flag(sub, a.params);
  sub.add_option("--out", a.out, "output dataset folder (new or empty)")->required();
  sub.add_flag("--force", a.force, "replace --out when it already holds files (written beside it, then swapped in)");
}

const Subcommand<SimulateArgs> kSimulateCommand{
    "simulate", "run a shear model over a scene and write the predicted field as a tsd/1 dataset", 30, add_flags,
    run_simulate};

}  // namespace
}  // namespace sb::app
