#pragma once
// What stands behind the public shearbench::SensorModel (include/shearbench/sensor_model.hpp), for
// shearbench's own programs: the CLI's simulate builds one from the sensor, indenter and parameters it has
// resolved, the bench times its step, and both use the Pose-typed step below. Consumers never see this file.
//
// A model form (hydroshear, fots, ...) runs as one batched kernel over the envs (core/models/any_batch.hpp);
// a form with effects as one ShearModel per env, stepped in parallel. Either way an env's field is bit for bit
// what ShearModel::step gives on the same path (the sensor's output stage applied per env, as make_model does).
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/base/params.hpp"
#include "core/geometry/indenter.hpp"
#include "core/models/any_batch.hpp"
#include "core/models/model.hpp"
#include "core/models/phase_profile.hpp"
#include "core/sensor/sensor.hpp"
#include "shearbench/sensor_model.hpp"

namespace shearbench {

struct SensorModel::Impl {
  // Throws std::invalid_argument for an unknown model (the message parse_model_spec gives) or envs < 1.
  // `sensor` and `indenter` are shared with the model and must not change while it lives.
  static SensorModel make(const std::string& model, std::shared_ptr<const sb::Sensor> sensor,
                          std::shared_ptr<const sb::Indenter> indenter, const sb::ParamSet& params, int envs);

  // One step of every env: X_EI.size() == envs, disp_px.size() == envs * markers; diagnostics empty or one per
  // env. Throws what the models throw (std::invalid_argument for a non-finite pose).
  void step_poses(std::span<const sb::Pose> X_EI, double dt, std::span<sb::Vec2> disp_px,
                  std::span<sb::FieldOutput> diagnostics = {});
  void reset();
  void reset(int env);
  // Phase timing of later batched steps into `profile` (nullptr: off; not owned). Forms with effects do not
  // time their phases.
  void set_profile(sb::PhaseProfile* profile);
  const sb::ParamSet& params() const;

  std::string model;
  int envs = 0;
  std::shared_ptr<const sb::Sensor> sensor;
  std::shared_ptr<const sb::Indenter> indenter;
  std::unique_ptr<sb::AnyBatch> batch;                   // a model form
  std::vector<std::unique_ptr<sb::ShearModel>> per_env;  // a form with effects: one per env
  // Scratch of the public step (reused: a step allocates nothing once sized).
  std::vector<sb::Pose> X_scratch;
  std::vector<sb::Vec2> disp_scratch;
  std::vector<sb::FieldOutput> diag_scratch;
};

// The benchmark workload's peg (BENCH_WORKLOAD.md): the capped cylinder's exact field and its 1992 points, no
// mesh (Config::indenter "bench_peg").
std::shared_ptr<const sb::Indenter> bench_peg_indenter();

}  // namespace shearbench
