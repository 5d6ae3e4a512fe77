// The public API (include/shearbench/sensor_model.hpp): the config resolved as `shearbench simulate` resolves
// its flags, then one batched kernel (or one ShearModel per env for a form with effects) behind a pose-array step.
#include "shearbench/sensor_model.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "core/api/bench_run.hpp"
#include "core/api/sensor_model_impl.hpp"
#include "core/base/data_root.hpp"
#include "core/base/error.hpp"
#include "core/base/install_paths.hpp"
#include "core/calibration/evaluate.hpp"
#include "core/calibration/param_sets.hpp"
#include "core/data/json_read.hpp"
#include "core/data/scene.hpp"
#include "core/effects/effects.hpp"
#include "core/effects/model_spec.hpp"
#include "core/geometry/sdf.hpp"
#include "core/models/bench_workload.hpp"

namespace fs = std::filesystem;

namespace shearbench {

Error::Error(const std::string& what) : std::runtime_error(what) {}
Error::~Error() = default;

namespace {

// Runs `f`, turning every exception into Error with the same message (the CLI prints e.what() too).
template <class F>
auto translated(F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(e.what());
  }
}

}  // namespace

std::shared_ptr<const sb::Indenter> bench_peg_indenter() {
  auto peg = std::make_shared<sb::Indenter>();
  peg->name = "bench_peg";
  peg->sdf = sb::make_capped_cylinder_sdf(sb::kPegRadius, sb::kPegLength);
  peg->samples = sb::bench_peg_points();
  return peg;
}

namespace {

struct Resolved {
  std::shared_ptr<const sb::Sensor> sensor;
  std::shared_ptr<const sb::Indenter> indenter;
  std::string sensor_model = sb::kDefaultSensorModel;
  nlohmann::json scene_params;  // the scene's table for the model (null: none)
};

nlohmann::json parse_block(const std::string& text, const std::string& what) {
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw Error(what + ": not JSON: " + e.what());
  }
}

Resolved resolve_sensor_and_indenter(const Config& c, const std::string& root) {
  Resolved r;
  const std::string cwd = fs::current_path().string();
  if (!c.scene.empty()) {
    if (!c.sensor.empty() || !c.indenter.empty())
      throw Error("scene: a scene gives the sensor and the indenter; leave sensor and indenter empty");
    const sb::Scene scene = sb::load_scene(c.scene, root);
    r.sensor = scene.sensor;
    r.sensor_model = scene.sensor_model;
    auto ind = std::make_shared<sb::Indenter>(
        sb::build_indenter(scene.indenter_spec, root, fs::path(c.scene).parent_path().string()));
    if (ind->name.empty()) ind->name = "indenter";
    r.indenter = ind;
    if (const auto it = scene.params.find(c.model); it != scene.params.end()) r.scene_params = it->second;
    return r;
  }
  r.sensor = c.sensor.empty() ? std::make_shared<const sb::Sensor>(sb::make_default_sensor())
                              : sb::parse_scene_sensor(parse_block(c.sensor, "sensor"), "sensor", root, cwd);
  if (c.indenter == "bench_peg") {
    r.indenter = bench_peg_indenter();
  } else {
    const nlohmann::json spec_json = c.indenter.empty() ? nlohmann::json{{"shape", "sphere"}, {"radius_m", 0.004}}
                                                        : parse_block(c.indenter, "indenter");
    const sb::IndenterSpec spec = sb::parse_indenter_spec(spec_json, "indenter", "", root, cwd);
    auto ind = std::make_shared<sb::Indenter>(sb::build_indenter(spec, root, cwd));
    if (ind->name.empty()) ind->name = "indenter";
    r.indenter = ind;
  }
  return r;
}

void require_model(const std::string& model) {
  try {
    (void)sb::parse_model_spec(model);
  } catch (const std::invalid_argument& e) {
    throw Error(std::string("model: ") + e.what());
  }
}

void check_size(std::size_t got, std::size_t want, const char* what, const char* shape) {
  if (got != want)
    throw Error(std::string(what) + ": " + std::to_string(got) + " values, expected " + std::to_string(want) + " (" +
                shape + ")");
}

// X[env] from 7 values, as make_pose builds it (the API's field is then ShearModel::step's bit for bit).
sb::Pose pose_at(std::span<const double> v, int env, const char* what) {
  const double* p = v.data() + static_cast<std::size_t>(env) * kPoseValues;
  for (int i = 0; i < kPoseValues; ++i)
    if (!std::isfinite(p[i]))
      throw Error(std::string(what) + "[env " + std::to_string(env) + "]: a pose value is not finite");
  if (p[3] * p[3] + p[4] * p[4] + p[5] * p[5] + p[6] * p[6] < sb::kQuatMinNorm * sb::kQuatMinNorm)
    throw Error(std::string(what) + "[env " + std::to_string(env) + "]: quaternion has zero norm");
  return sb::make_pose(sb::Vec3(p[0], p[1], p[2]), p[3], p[4], p[5], p[6]);
}

}  // namespace

// ---------------------------------------------------------------- Impl

SensorModel SensorModel::Impl::make(const std::string& model, std::shared_ptr<const sb::Sensor> sensor,
                                    std::shared_ptr<const sb::Indenter> indenter, const sb::ParamSet& params,
                                    int envs) {
  if (envs < 1) throw std::invalid_argument("envs: must be >= 1, not " + std::to_string(envs));
  auto m = std::make_unique<Impl>();
  m->model = model;
  m->envs = envs;
  m->sensor = std::move(sensor);
  m->indenter = std::move(indenter);
  if (sb::has_batch(model)) {
    m->batch = sb::make_batch(model, m->sensor, m->indenter, envs, params);
  } else {
    auto first = sb::make_spec_model(model, m->sensor, m->indenter);
    first->set_params(params);
    m->per_env.reserve(envs);
    for (int e = 1; e < envs; ++e) m->per_env.push_back(first->clone());
    m->per_env.insert(m->per_env.begin(), std::move(first));
  }
  return SensorModel(std::move(m));
}

const sb::ParamSet& SensorModel::Impl::params() const { return batch ? batch->params() : per_env.front()->params(); }

void SensorModel::Impl::step_poses(std::span<const sb::Pose> X_EI, double dt, std::span<sb::Vec2> disp_px,
                                   std::span<sb::FieldOutput> diagnostics) {
  const std::size_t M = sensor->p_EM.size();
  if (batch) {
    batch->step(X_EI, dt, disp_px, diagnostics);
    if (sensor->output_stage.identity()) return;
    // The sensor's output stage per env (pins at depth, a perspective camera), as make_model's models apply it.
    std::vector<sb::Vec2> one(M);
    for (int e = 0; e < envs; ++e) {
      std::copy_n(disp_px.begin() + static_cast<std::ptrdiff_t>(e * M), M, one.begin());
      sensor->output_stage.apply(one);
      std::copy(one.begin(), one.end(), disp_px.begin() + static_cast<std::ptrdiff_t>(e * M));
      if (!diagnostics.empty()) diagnostics[e].disp_px = one;
    }
    return;
  }
  // Forms with effects: check every pose first, so a bad one leaves every env's state unchanged.
  for (const sb::Pose& X : X_EI)
    if (!sb::is_finite(X)) throw std::invalid_argument(model + ": the indenter pose X_EI is not finite");
  tbb::parallel_for(0, envs, [&](int e) {
    sb::FieldOutput local;
    sb::FieldOutput& out = diagnostics.empty() ? local : diagnostics[e];
    per_env[e]->step(X_EI[e], dt, &out);
    std::copy(out.disp_px.begin(), out.disp_px.end(), disp_px.begin() + static_cast<std::ptrdiff_t>(e * M));
  });
}

void SensorModel::Impl::reset() {
  if (batch) batch->reset();
  for (auto& m : per_env) m->reset();
}

void SensorModel::Impl::reset(int env) {
  if (env < 0 || env >= envs)
    throw std::invalid_argument("reset: env " + std::to_string(env) + " outside 0.." + std::to_string(envs - 1));
  if (batch)
    batch->reset_slot(env);
  else
    per_env[env]->reset();
}

void SensorModel::Impl::set_profile(sb::PhaseProfile* profile) {
  if (batch) batch->set_profile(profile);
}

// ---------------------------------------------------------------- SensorModel

SensorModel::SensorModel(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
SensorModel::~SensorModel() = default;
SensorModel::SensorModel(SensorModel&&) noexcept = default;
SensorModel& SensorModel::operator=(SensorModel&&) noexcept = default;

SensorModel SensorModel::create(const Config& c) {
  return translated([&] {
    require_model(c.model);
    if (c.envs < 1) throw Error("envs: must be >= 1, not " + std::to_string(c.envs));
    const std::string root = sb::resolve_data_root(c.data_root);
    const Resolved r = resolve_sensor_and_indenter(c, root);
    // As `simulate`: the set (default: the sensor's), then the scene's table, then the params file.
    const sb::NamedParamSet set = sb::load_param_set(sb::param_set_or_default(c.param_set, r.sensor_model));
    sb::ParamSet params = set.params(c.model);
    if (!r.scene_params.is_null()) params.update_from_json(r.scene_params, c.scene + ": /params/" + c.model);
    if (!c.params_file.empty())
      params.update_from_json(sb::params_for_model(sb::jsonin::load_file(c.params_file), c.model, true, c.params_file),
                              c.params_file);
    return Impl::make(c.model, r.sensor, r.indenter, params, c.envs);
  });
}

const std::string& SensorModel::model() const { return impl_->model; }
int SensorModel::envs() const { return impl_->envs; }
int SensorModel::markers() const { return static_cast<int>(impl_->sensor->p_EM.size()); }

std::vector<double> SensorModel::markers_rest_px() const {
  std::vector<double> v;
  v.reserve(2 * impl_->sensor->markers_rest_px.size());
  for (const sb::Vec2& m : impl_->sensor->markers_rest_px) v.insert(v.end(), {m.x(), m.y()});
  return v;
}

double SensorModel::mm_per_px() const {
  if (impl_->sensor->camera.pinhole())
    throw Error("mm_per_px: the sensor's camera is a pinhole; its scale varies across the image");
  return impl_->sensor->camera.mm_per_px;
}

std::string SensorModel::params_json() const { return impl_->params().to_json().dump(); }

void SensorModel::step(std::span<const double> X_EI, double dt, std::span<double> disp_px,
                       std::span<std::uint8_t> in_contact) {
  translated([&] {
    Impl& m = *impl_;
    const std::size_t E = m.envs, M = m.sensor->p_EM.size();
    check_size(X_EI.size(), E * kPoseValues, "X_EI", "envs x 7");
    check_size(disp_px.size(), E * M * 2, "disp_px", "envs x markers x 2");
    if (!in_contact.empty()) check_size(in_contact.size(), E * M, "in_contact", "envs x markers");
    if (!std::isfinite(dt) || dt <= 0) throw Error("dt: must be finite and > 0, not " + std::to_string(dt));
    m.X_scratch.resize(E);
    for (std::size_t e = 0; e < E; ++e) m.X_scratch[e] = pose_at(X_EI, static_cast<int>(e), "X_EI");
    m.disp_scratch.resize(E * M);
    m.diag_scratch.resize(in_contact.empty() ? 0 : E);
    m.step_poses(m.X_scratch, dt, m.disp_scratch, m.diag_scratch);
    // Vec2 is 16-byte aligned in Eigen; a caller's buffer need not be, so the field is copied out (a memcpy).
    for (std::size_t i = 0; i < E * M; ++i) {
      disp_px[2 * i] = m.disp_scratch[i].x();
      disp_px[2 * i + 1] = m.disp_scratch[i].y();
    }
    for (std::size_t e = 0; e < m.diag_scratch.size(); ++e) {
      const auto& flags = m.diag_scratch[e].marker_in_contact;
      for (std::size_t j = 0; j < M; ++j) in_contact[e * M + j] = j < flags.size() ? flags[j] : 0;
    }
  });
}

void SensorModel::step_world(std::span<const double> X_WE, std::span<const double> X_WI, double dt,
                             std::span<double> disp_px, std::span<std::uint8_t> in_contact) {
  const std::size_t E = impl_->envs;
  check_size(X_WE.size(), E * kPoseValues, "X_WE", "envs x 7");
  check_size(X_WI.size(), E * kPoseValues, "X_WI", "envs x 7");
  std::vector<double> X_EI(E * kPoseValues);
  translated([&] {
    for (std::size_t e = 0; e < E; ++e) {
      const sb::Pose X = pose_at(X_WE, static_cast<int>(e), "X_WE").inverse(Eigen::Isometry) *
                         pose_at(X_WI, static_cast<int>(e), "X_WI");
      const sb::Quat q(X.linear());
      const double v[kPoseValues] = {
          X.translation().x(), X.translation().y(), X.translation().z(), q.w(), q.x(), q.y(), q.z()};
      std::copy(v, v + kPoseValues, X_EI.begin() + static_cast<std::ptrdiff_t>(e * kPoseValues));
    }
  });
  step(X_EI, dt, disp_px, in_contact);
}

void SensorModel::reset() { impl_->reset(); }
void SensorModel::reset(int env) {
  translated([&] { impl_->reset(env); });
}

// ---------------------------------------------------------------- free functions

std::vector<std::string> model_names() { return sb::model_ids(); }
std::vector<std::string> effect_names() { return sb::effect_ids(); }
std::vector<std::string> param_set_names() {
  return translated([] { return sb::param_set_names(); });
}

Config loop_answer(const std::string& run_name) {
  return translated([&] {
    const fs::path file = fs::path(sb::home_dir()) / "docs" / "residuals" / run_name / "report_params.json";
    if (run_name.empty() || run_name.find('/') != std::string::npos || !fs::is_regular_file(file))
      throw sb::InputError(file.string(),
                           "no residual run '" + run_name + "' (docs/residuals/<run>/report_params.json)");
    const nlohmann::json j = sb::jsonin::load_file(file.string());
    if (!j.is_object() || j.size() != 1 || !j.begin().value().is_object())
      throw sb::InputError(file.string(), "expected one model's table, {\"<model>\": {...}}");
    Config c;
    c.model = j.begin().key();
    c.params_file = file.string();
    return c;
  });
}

std::vector<double> bench_poses(int envs, int steps) {
  return translated([&] {
    if (envs < 1) throw Error("bench_poses: envs must be >= 1");
    if (steps < 1 || steps > sb::kBenchMaxSteps)
      throw Error("bench_poses: steps must be in 1.." + std::to_string(sb::kBenchMaxSteps));
    sb::BenchWorkloadSpec spec;
    spec.envs = envs;
    spec.steps = steps;
    std::vector<double> v;
    v.reserve(static_cast<std::size_t>(steps) * envs * sb::kBenchSensors * kPoseValues);
    for (const auto& step : sb::bench_trajectory(spec))
      for (const sb::Pose& X : step) {
        const sb::Quat q(X.linear());
        v.insert(v.end(), {X.translation().x(), X.translation().y(), X.translation().z(), q.w(), q.x(), q.y(), q.z()});
      }
    return v;
  });
}

double bench_dt() { return sb::kBenchDt; }

std::string version() { return SHEARBENCH_VERSION; }

}  // namespace shearbench
