#include "core/api/bench_run.hpp"

#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "core/api/sensor_model_impl.hpp"
#include "core/models/bench_workload.hpp"
#include "core/models/model.hpp"

namespace sb {

// Every model form is benchmarked, in display order.
const std::vector<std::string>& bench_model_ids() { return model_ids(); }

Stats bench_stats(std::vector<double> v) {
  if (v.empty()) throw std::invalid_argument("bench_stats: no values");
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  const double median = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  return {median, v.front(), v.back()};
}

struct BenchWorkload::Impl {
  // [step][(env * 2 + sensor) * 7 + i]: the poses as the public API takes them (shearbench::bench_poses), so
  // a consumer stepping those gets this field bit for bit.
  std::vector<std::vector<double>> X_EI;
  std::optional<shearbench::SensorModel> model;
  std::vector<double> disp;  // [slot][marker][2]
  PhaseProfile profile;
};

BenchWorkload::BenchWorkload(const std::string& model, int envs, int steps)
    : model_(model), envs_(envs), steps_(steps), impl_(std::make_unique<Impl>()) {
  if (envs < 1) throw std::invalid_argument("bench: --envs must be >= 1");
  if (steps <= kBenchWarmupSteps || steps > kBenchMaxSteps)
    throw std::invalid_argument("bench: --steps must be in " + std::to_string(kBenchWarmupSteps + 1) + ".." +
                                std::to_string(kBenchMaxSteps));
  BenchWorkloadSpec spec;
  spec.envs = envs;
  spec.steps = steps;
  const auto& ids = bench_model_ids();
  if (std::find(ids.begin(), ids.end(), model) == ids.end())
    throw std::invalid_argument("bench: unknown model '" + model + "'");
  const int slots = envs * kBenchSensors;
  const std::vector<double> poses = shearbench::bench_poses(envs, steps);
  const std::size_t per_step = static_cast<std::size_t>(slots) * shearbench::kPoseValues;
  for (int k = 0; k < steps; ++k)
    impl_->X_EI.emplace_back(poses.begin() + static_cast<std::ptrdiff_t>(k * per_step),
                             poses.begin() + static_cast<std::ptrdiff_t>((k + 1) * per_step));
  // The published values (the workload's definition), the GelSight Mini and the peg.
  auto sensor = std::make_shared<const Sensor>(make_default_sensor());
  impl_->model.emplace(shearbench::SensorModel::Impl::make(model, sensor, shearbench::bench_peg_indenter(),
                                                           default_params(model), slots));
  impl_->disp.assign(static_cast<std::size_t>(slots) * sensor->p_EM.size() * 2, 0.0);
}

BenchWorkload::~BenchWorkload() = default;
BenchWorkload::BenchWorkload(BenchWorkload&&) noexcept = default;

BenchResult BenchWorkload::run(bool profile) {
  using Clock = std::chrono::steady_clock;
  Impl& m = *impl_;
  shearbench::SensorModel::Impl& api = m.model->impl();
  api.reset();
  m.profile.clear();
  api.set_profile(nullptr);
  BenchResult r;
  r.model = model_;
  r.envs = envs_;
  r.slots = envs_ * kBenchSensors;
  r.steps = steps_;
  r.timed_steps = steps_ - kBenchWarmupSteps;
  r.threads = tbb::this_task_arena::max_concurrency();
  r.profiled = profile;
  r.step_ms.resize(steps_);
  for (int k = 0; k < steps_; ++k) {
    // The profile covers the timed steps only.
    if (profile && k == kBenchWarmupSteps) api.set_profile(&m.profile);
    const Clock::time_point t0 = Clock::now();
    m.model->step(m.X_EI[k], kBenchDt, m.disp);
    r.step_ms[k] = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  }
  api.set_profile(nullptr);
  const Stats s = bench_stats({r.step_ms.begin() + kBenchWarmupSteps, r.step_ms.end()});
  r.median_ms = s.median;
  r.min_ms = s.min;
  r.max_ms = s.max;
  r.sensor_steps_per_s = r.slots / (1e-3 * r.median_ms);
  for (int i = 0; i < kPhaseCount; ++i) r.phase_cpu_ms[i] = m.profile.ms(static_cast<Phase>(i)) / r.timed_steps;
  for (std::size_t i = 0; i + 1 < m.disp.size(); i += 2) r.checksum += std::hypot(m.disp[i], m.disp[i + 1]);
  return r;
}

const std::vector<double>& BenchWorkload::last_field() const { return impl_->disp; }

}  // namespace sb
