// Shear-model step costs: one sensor with a 4 mm sphere (single-instance ShearModel), and the batched
// peg workload of BENCH_WORKLOAD.md (steps 3..22 timed, state carried from step 0; manual time is the
// median batched step). Run: ./build/shearbench_bench --benchmark_filter='Models|Workload'

#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>

#include "core/api/bench_run.hpp"
#include "core/models/model.hpp"

namespace {

std::shared_ptr<const sb::Sensor> mini_sensor() {
  auto s = std::make_shared<sb::Sensor>();
  for (int r = 0; r < 7; ++r)
    for (int c = 0; c < 9; ++c) {
      const sb::Vec2 uv(s->camera.principal_px.x() + (c - 4) * 33.0, s->camera.principal_px.y() + (r - 3) * 33.0);
      s->markers_rest_px.push_back(uv);
      const sb::Vec2 xy = s->camera.E_from_px(uv);
      s->p_EM.emplace_back(xy.x(), xy.y(), 0.0);
    }
  s->gel_sdf = sb::make_pad_sdf(s->gel.size_m, s->gel.thickness_m);
  return s;
}

std::shared_ptr<const sb::Indenter> sphere(double r, int n) {
  auto ind = std::make_shared<sb::Indenter>();
  ind->sdf = sb::make_sphere_sdf(r);
  const double golden = std::numbers::pi * (3 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1 - (2.0 * i + 1) / n, rho = std::sqrt(1 - z * z);
    const sb::Vec3 d(rho * std::cos(golden * i), rho * std::sin(golden * i), z);
    ind->samples.p_IS.push_back(r * d);
    ind->samples.n_IS.push_back(d);
    ind->samples.area_m2.push_back(4 * std::numbers::pi * r * r / n);
  }
  return ind;
}

// 4 mm sphere (~360 points at 0.75 mm) pressed 1 mm and sliding: one ShearModel step.
void BM_Models_SingleSphere(benchmark::State& state, const std::string& id) {
  auto m = sb::make_model(id, mini_sensor(), sphere(0.004, 360));
  sb::FieldOutput out;
  int k = 0;
  for (auto _ : state) {
    const double x = 1e-5 * (k % 100);
    sb::Pose X = sb::Pose::Identity();
    X.translation() = sb::Vec3(x, 0, 0.004 - 1e-3);
    m->step(X, 0.01, &out);
    ++k;
    benchmark::DoNotOptimize(out.disp_px.data());
  }
}
BENCHMARK_CAPTURE(BM_Models_SingleSphere, hydroshear, std::string("hydroshear"));
BENCHMARK_CAPTURE(BM_Models_SingleSphere, fots, std::string("fots"));
BENCHMARK_CAPTURE(BM_Models_SingleSphere, fots_reimpl, std::string("fots-reimpl"));
BENCHMARK_CAPTURE(BM_Models_SingleSphere, tacsl, std::string("tacsl"));

// BENCH_WORKLOAD.md through the same code as `shearbench bench` (core/api/bench_run: the public API's
// SensorModel::step, the C++ side of bench/bench_python.py's ratio): each iteration resets
// the batch and runs steps k = 0..22; the manual time is the median batched step over k = 3..22
// (counters: that run's min and max, and sensor-steps per second). BM_Workload/<model>/<envs>.
void BM_Workload(benchmark::State& state, const std::string& model, int envs) {
  sb::BenchWorkload w(model, envs);
  sb::BenchResult last;
  for (auto _ : state) {
    last = w.run(false);
    state.SetIterationTime(1e-3 * last.median_ms);
  }
  state.counters["min_ms"] = last.min_ms;
  state.counters["max_ms"] = last.max_ms;
  state.counters["sensor_steps_per_s"] = last.sensor_steps_per_s;
}

// Registered at start-up: one case per model and env count.
const bool kWorkloadRegistered = [] {
  for (const std::string& model : sb::bench_model_ids())
    for (int envs : {256, 512, 1024})
      benchmark::RegisterBenchmark(("BM_Workload/" + model + "/" + std::to_string(envs)).c_str(),
                                   [model, envs](benchmark::State& st) { BM_Workload(st, model, envs); })
          ->UseManualTime()
          ->Unit(benchmark::kMillisecond)
          ->Iterations(5);
  return true;
}();

}  // namespace
