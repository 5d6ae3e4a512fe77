// Shear-model step costs: one sensor with a 4 mm sphere (single-instance ShearModel), and the batched
// peg workload of BENCH_WORKLOAD.md (steps 3..22 timed, state carried from step 0; manual time is the
// mean per batched step). Run: ./build/shearbench_bench --benchmark_filter=Models
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <numbers>

#include "core/bench_workload.hpp"
#include "core/fots.hpp"
#include "core/hydroshear.hpp"
#include "core/model.hpp"
#include "core/tacsl.hpp"

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

template <class Batch, class Make>
void run_workload(benchmark::State& state, Make make) {
  sb::BenchWorkloadSpec spec;
  spec.envs = static_cast<int>(state.range(0));
  const auto traj = sb::bench_trajectory(spec);
  auto peg = std::make_shared<sb::Indenter>();
  peg->sdf = sb::make_capped_cylinder_sdf(sb::kPegRadius, sb::kPegLength);
  peg->samples = sb::bench_peg_points();
  const int slots = spec.envs * sb::kBenchSensors;
  Batch batch = make(mini_sensor(), peg, slots);
  std::vector<sb::Vec2> disp(static_cast<std::size_t>(slots) * 63);
  for (auto _ : state) {
    batch.reset();
    for (int k = 0; k < 3; ++k) batch.step(traj[k], 1.0 / 60, disp, {});
    const auto t0 = std::chrono::steady_clock::now();
    for (int k = 3; k < 23; ++k) batch.step(traj[k], 1.0 / 60, disp, {});
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    state.SetIterationTime(s / 20);
  }
}

void BM_Models_Workload_HydroShear(benchmark::State& st) {
  run_workload<sb::HydroShearBatch>(st, [](auto s, auto i, int n) {
    return sb::HydroShearBatch(s, i, n, sb::default_params("hydroshear"));
  });
}
void BM_Models_Workload_FotsReimpl(benchmark::State& st) {
  run_workload<sb::FotsBatch>(st, [](auto s, auto i, int n) {
    return sb::FotsBatch(sb::FotsVariant::Reimpl, s, i, n, sb::default_params("fots-reimpl"));
  });
}
void BM_Models_Workload_Tacsl(benchmark::State& st) {
  run_workload<sb::TacslBatch>(st, [](auto s, auto i, int n) {
    return sb::TacslBatch(false, s, i, n, sb::default_params("tacsl"));
  });
}
BENCHMARK(BM_Models_Workload_HydroShear)->Arg(1024)->UseManualTime()->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_Models_Workload_FotsReimpl)->Arg(1024)->UseManualTime()->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_Models_Workload_Tacsl)->Arg(1024)->UseManualTime()->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
