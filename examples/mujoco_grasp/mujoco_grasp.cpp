// The benchmark's peg grasp driven by a real physics engine: MuJoCo steps the gripper of peg_grasp.xml (close,
// slide, twist), and after every physics step the peg's pose in each pad's gel frame goes to one batched
// shearbench::SensorModel (2 envs: the left and the right pad). Writes
//   OUT/log/          a tsd/1 dataset, one sample per pad (left_pad, right_pad): the poses and the model's field
//   OUT/left_pad.json, OUT/right_pad.json   scenes replaying each pad's poses (`shearbench simulate` reproduces
//                     the field from them)
//   OUT/timing.json   physics and tactile milliseconds per step
// Usage: mujoco_grasp --mjcf examples/mujoco_grasp/peg_grasp.xml --out DIR [--model hydroshear] [--param-set S]
#include <mujoco/mujoco.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <shearbench/sensor_model.hpp>
#include <string>
#include <vector>

#include "core/base/atomic_write.hpp"
#include "core/base/error.hpp"
#include "core/data/tsd.hpp"
#include "core/geometry/indenter.hpp"
#include "core/geometry/mesh.hpp"
#include "core/sensor/sensor.hpp"

namespace fs = std::filesystem;

namespace {

// The peg of BENCH_WORKLOAD.md as a scene's indenter block (its axis is body z, as MuJoCo's cylinder's).
const char* kPegJson = R"({"shape": "cylinder", "radius_m": 0.004, "length_m": 0.04, "fillet_m": 0})";
constexpr std::array<const char*, 2> kPads = {"left_pad", "right_pad"};

// The grasp's schedule: targets of the actuators at time t (s). Pads close 3.2 mm (contact at 2.8 mm), then
// the hand slides 2 mm along the peg and 1 mm across, then twists 6 degrees about the grasp axis.
struct Targets {
  double close_m, x_m, z_m, twist_rad;
};
double ramp(double t, double t0, double t1) { return std::clamp((t - t0) / (t1 - t0), 0.0, 1.0); }
Targets schedule(double t) {
  const double pi = 3.14159265358979323846;
  return {3.2e-3 * ramp(t, 0.0, 0.15), 1.0e-3 * ramp(t, 0.25, 0.65), 2.0e-3 * ramp(t, 0.25, 0.65),
          6.0 * pi / 180 * ramp(t, 0.75, 1.05)};
}
constexpr double kDuration = 1.2;  // s

struct MjDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
  void operator()(mjData* d) const { mj_deleteData(d); }
};

int id_of(const mjModel* m, mjtObj type, const char* name) {
  const int id = mj_name2id(m, type, name);
  if (id < 0) throw sb::InputError("peg_grasp.xml", std::string("no ") + name);
  return id;
}

// X_EI of the peg in a pad's frame from MuJoCo's body poses: X_WE^-1 X_WI (mju_negPose, mju_mulPose).
void peg_in_pad(const mjData* d, int pad, int peg, double* X_EI) {
  mjtNum p_EW[3], q_EW[4];
  mju_negPose(p_EW, q_EW, d->xpos + 3 * pad, d->xquat + 4 * pad);
  mju_mulPose(X_EI, X_EI + 3, p_EW, q_EW, d->xpos + 3 * peg, d->xquat + 4 * peg);
}

struct Log {
  std::vector<double> t_s;
  std::array<std::vector<std::array<double, 7>>, 2> X_EI;
  std::array<std::vector<std::vector<sb::Vec2>>, 2> disp_px;
};

void write_log(const std::string& dir, const Log& log, const std::string& model, const std::string& params_json,
               double dt) {
  sb::Dataset ds;
  ds.name = "mujoco_peg_grasp";
  ds.kind = "synthetic";
  ds.license = "CC0-1.0";
  ds.provenance = "shearbench mujoco_grasp: MuJoCo " + std::string(mj_versionString()) +
                  " stepping examples/mujoco_grasp/peg_grasp.xml; the field from shearbench's " + model +
                  " (the public API), one sample per pad";
  const sb::Sensor sensor = sb::make_default_sensor();
  ds.camera = sensor.camera;
  ds.gel = sensor.gel;
  ds.markers_rest_px = sensor.markers_rest_px;
  // "sensors": the samples recorded at the same frames, one per pad; the workbench's replay of one shows the
  // other's field beside it.
  ds.extra["shearbench"] = {
      {"model", model}, {"params", nlohmann::json::parse(params_json)}, {"sensors", {kPads[0], kPads[1]}}};
  ds.indenters["peg"] = sb::TsdIndenter{"meshes/peg.obj", nlohmann::json::object()};
  std::vector<sb::SampleData> samples;
  for (int s = 0; s < 2; ++s) {
    sb::TsdSampleInfo info;
    info.id = kPads[s];
    info.motion = "free";
    info.indenter = "peg";
    info.split = "validation";
    info.dt_s = dt;
    ds.samples.push_back(info);
    sb::SampleData data;
    for (std::size_t k = 0; k < log.t_s.size(); ++k) {
      const auto& x = log.X_EI[s][k];
      data.t_s.push_back(log.t_s[k]);
      data.p_EI.emplace_back(x[0], x[1], x[2]);
      data.q_EI.emplace_back(x[3], x[4], x[5], x[6]);
    }
    data.markers_px = log.disp_px[s];
    samples.push_back(std::move(data));
  }
  fs::create_directories(fs::path(dir) / "meshes");
  sb::IndenterSpec spec;
  spec.shape = "cylinder";
  spec.radius_m = 0.004;
  spec.length_m = 0.04;
  spec.fillet_m = 0;
  sb::save_obj(sb::make_indenter_mesh(spec, "", ""), (fs::path(dir) / "meshes/peg.obj").string());
  sb::write_dataset(dir, ds, samples);
}

// A scene replaying one pad's poses from the log, with the peg's exact shape: `shearbench simulate` on it gives
// that pad's field of the log.
void write_scene(const std::string& path, const std::string& log_dir, const char* pad) {
  const nlohmann::ordered_json j = {
      {"name", std::string("mujoco_grasp_") + pad},
      {"description", std::string("the MuJoCo peg grasp's ") + pad + " (examples/mujoco_grasp): its logged poses"},
      {"indenter", nlohmann::json::parse(kPegJson)},
      {"dataset", {{"path", fs::absolute(log_dir).lexically_normal().string()}, {"sample", pad}}}};
  sb::write_file_atomic(path, j.dump(2) + "\n");
}

int run(const std::string& mjcf, const std::string& out, const std::string& model_name, const std::string& set) {
  char error[1000] = "";
  std::unique_ptr<mjModel, MjDeleter> m(mj_loadXML(mjcf.c_str(), nullptr, error, sizeof error));
  if (!m) throw sb::InputError(mjcf, std::string("MuJoCo could not load it: ") + error);
  std::unique_ptr<mjData, MjDeleter> d(mj_makeData(m.get()));
  const int peg = id_of(m.get(), mjOBJ_BODY, "peg");
  const std::array<int, 2> pads = {id_of(m.get(), mjOBJ_BODY, kPads[0]), id_of(m.get(), mjOBJ_BODY, kPads[1])};
  const std::array<int, 5> act = {id_of(m.get(), mjOBJ_ACTUATOR, "left_close"),
                                  id_of(m.get(), mjOBJ_ACTUATOR, "right_close"),
                                  id_of(m.get(), mjOBJ_ACTUATOR, "hand_x"), id_of(m.get(), mjOBJ_ACTUATOR, "hand_z"),
                                  id_of(m.get(), mjOBJ_ACTUATOR, "hand_twist")};

  shearbench::Config config;
  config.model = model_name;
  config.param_set = set;
  config.indenter = kPegJson;
  config.envs = 2;  // env 0: the left pad, env 1: the right pad
  shearbench::SensorModel tactile = shearbench::SensorModel::create(config);
  const std::size_t M = tactile.markers();
  std::vector<double> X_EI(2 * shearbench::kPoseValues), field(2 * M * 2);

  using Clock = std::chrono::steady_clock;
  double physics_s = 0, tactile_s = 0;
  Log log;
  const double dt = m->opt.timestep;
  const int steps = static_cast<int>(std::lround(kDuration / dt));
  mj_forward(m.get(), d.get());  // body poses at t = 0 (frame 0: the pads open, out of contact)
  for (int k = 0; k <= steps; ++k) {
    if (k > 0) {
      const Targets c = schedule(d->time);
      d->ctrl[act[0]] = d->ctrl[act[1]] = c.close_m;
      d->ctrl[act[2]] = c.x_m;
      d->ctrl[act[3]] = c.z_m;
      d->ctrl[act[4]] = c.twist_rad;
      const Clock::time_point t0 = Clock::now();
      mj_step(m.get(), d.get());
      physics_s += std::chrono::duration<double>(Clock::now() - t0).count();
    }
    const Clock::time_point t1 = Clock::now();
    for (int s = 0; s < 2; ++s) peg_in_pad(d.get(), pads[s], peg, X_EI.data() + s * shearbench::kPoseValues);
    // The first step after rest has no elapsed time; the models take the physics step's.
    tactile.step(X_EI, dt, field);
    tactile_s += std::chrono::duration<double>(Clock::now() - t1).count();

    log.t_s.push_back(d->time);
    for (int s = 0; s < 2; ++s) {
      std::array<double, 7> x{};
      std::copy_n(X_EI.begin() + s * shearbench::kPoseValues, 7, x.begin());
      log.X_EI[s].push_back(x);
      std::vector<sb::Vec2> f(M);
      for (std::size_t j = 0; j < M; ++j) f[j] = {field[(s * M + j) * 2], field[(s * M + j) * 2 + 1]};
      log.disp_px[s].push_back(std::move(f));
    }
  }

  const std::string log_dir = (fs::path(out) / "log").string();
  write_log(log_dir, log, model_name, tactile.params_json(), dt);
  for (int s = 0; s < 2; ++s)
    write_scene((fs::path(out) / (std::string(kPads[s]) + ".json")).string(), log_dir, kPads[s]);
  double peak = 0;
  for (const auto& pad : log.disp_px)
    for (const auto& f : pad)
      for (const sb::Vec2& v : f) peak = std::max(peak, v.norm());
  const nlohmann::ordered_json timing = {{"steps", steps},
                                         {"dt_s", dt},
                                         {"model", model_name},
                                         {"sensors", 2},
                                         {"physics_ms_per_step", 1e3 * physics_s / steps},
                                         {"tactile_ms_per_step", 1e3 * tactile_s / (steps + 1)},
                                         {"peak_displacement_px", peak}};
  sb::write_file_atomic((fs::path(out) / "timing.json").string(), timing.dump(2) + "\n");
  std::printf(
      "mujoco_grasp: %d MuJoCo steps of %.3g ms, %s on both pads: physics %.4f ms, tactile %.4f ms per step; "
      "peak |disp| %.2f px -> %s\n",
      steps, 1e3 * dt, model_name.c_str(), 1e3 * physics_s / steps, 1e3 * tactile_s / (steps + 1), peak, out.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"the peg grasp stepped by MuJoCo, both pads' tactile field from shearbench each step"};
  std::string mjcf, out, model = "hydroshear", set;
  app.add_option("--mjcf", mjcf, "the MuJoCo model (examples/mujoco_grasp/peg_grasp.xml)")->required();
  app.add_option("--out", out, "output folder: log/ (tsd/1), left_pad.json, right_pad.json, timing.json")->required();
  app.add_option("--model", model, "the shear model (a shearbench model name)")->capture_default_str();
  app.add_option("--param-set", set, "a parameter set (default: the GelSight Mini's)");
  CLI11_PARSE(app, argc, argv);
  try {
    return run(mjcf, out, model, set);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mujoco_grasp: error: %s\n", e.what());
    return 2;
  }
}
