#include "core/models/bench_run.hpp"

#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include "core/geometry/sdf.hpp"
#include "core/models/bench_workload.hpp"
#include "core/models/fots.hpp"
#include "core/models/hydroshear.hpp"
#include "core/models/tacsl.hpp"

namespace sb {

const std::vector<std::string>& bench_model_ids() {
  static const std::vector<std::string> ids = {"hydroshear",        "fots",
                                               "fots-reimpl",       "tacsl",
                                               "tacsl-normalized",  "hydroshear-layer",
                                               "hydroshear-stick",  "hydroshear-layer-stick",
                                               "hydroshear-contact"};
  return ids;
}

Stats bench_stats(std::vector<double> v) {
  if (v.empty()) throw std::invalid_argument("bench_stats: no values");
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  const double median = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  return {median, v.front(), v.back()};
}

namespace {

// The three batch classes behind one interface (they share the step signature, not a base class).
struct AnyBatch {
  virtual ~AnyBatch() = default;
  virtual void reset() = 0;
  virtual void set_profile(PhaseProfile* p) = 0;
  virtual void step(std::span<const Pose> X_EI, double dt, std::span<Vec2> disp) = 0;
};

template <class Batch>
struct BatchOf final : AnyBatch {
  explicit BatchOf(Batch b) : batch(std::move(b)) {}
  void reset() override { batch.reset(); }
  void set_profile(PhaseProfile* p) override { batch.set_profile(p); }
  void step(std::span<const Pose> X_EI, double dt, std::span<Vec2> disp) override { batch.step(X_EI, dt, disp, {}); }
  Batch batch;
};

std::unique_ptr<AnyBatch> make_batch(const std::string& model, std::shared_ptr<const Sensor> sensor,
                                     std::shared_ptr<const Indenter> peg, int slots) {
  const ParamSet params = default_params(model);
  if (model.rfind("hydroshear", 0) == 0)
    return std::make_unique<BatchOf<HydroShearBatch>>(HydroShearBatch(sensor, peg, slots, params));
  if (model == "fots")
    return std::make_unique<BatchOf<FotsBatch>>(FotsBatch(FotsVariant::Original, sensor, peg, slots, params));
  if (model == "fots-reimpl")
    return std::make_unique<BatchOf<FotsBatch>>(FotsBatch(FotsVariant::Reimpl, sensor, peg, slots, params));
  if (model == "tacsl") return std::make_unique<BatchOf<TacslBatch>>(TacslBatch(false, sensor, peg, slots, params));
  if (model == "tacsl-normalized")
    return std::make_unique<BatchOf<TacslBatch>>(TacslBatch(true, sensor, peg, slots, params));
  throw std::invalid_argument("bench: unknown model '" + model + "'");
}

}  // namespace

struct BenchWorkload::Impl {
  std::vector<std::vector<Pose>> X_EI;  // [step][env * 2 + sensor]
  std::unique_ptr<AnyBatch> batch;
  std::vector<Vec2> disp;
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
  impl_->X_EI = bench_trajectory(spec);
  auto sensor = std::make_shared<Sensor>(make_default_sensor());
  auto peg = std::make_shared<Indenter>();
  peg->name = "bench_peg";
  peg->sdf = make_capped_cylinder_sdf(kPegRadius, kPegLength);
  peg->samples = bench_peg_points();
  const int slots = envs * kBenchSensors;
  impl_->batch = make_batch(model, sensor, peg, slots);
  impl_->disp.assign(static_cast<std::size_t>(slots) * sensor->p_EM.size(), Vec2::Zero());
}

BenchWorkload::~BenchWorkload() = default;
BenchWorkload::BenchWorkload(BenchWorkload&&) noexcept = default;

BenchResult BenchWorkload::run(bool profile) {
  using Clock = std::chrono::steady_clock;
  Impl& m = *impl_;
  m.batch->reset();
  m.profile.clear();
  m.batch->set_profile(nullptr);
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
    if (profile && k == kBenchWarmupSteps) m.batch->set_profile(&m.profile);
    const Clock::time_point t0 = Clock::now();
    m.batch->step(m.X_EI[k], kBenchDt, m.disp);
    r.step_ms[k] = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  }
  m.batch->set_profile(nullptr);
  const Stats s = bench_stats({r.step_ms.begin() + kBenchWarmupSteps, r.step_ms.end()});
  r.median_ms = s.median;
  r.min_ms = s.min;
  r.max_ms = s.max;
  r.sensor_steps_per_s = r.slots / (1e-3 * r.median_ms);
  for (int i = 0; i < kPhaseCount; ++i) r.phase_cpu_ms[i] = m.profile.ms(static_cast<Phase>(i)) / r.timed_steps;
  for (const Vec2& d : m.disp) r.checksum += d.norm();
  return r;
}

}  // namespace sb
