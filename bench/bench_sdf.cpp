// Mesh SDF cost: OpenVDB narrow-band build of a 10k-vertex icosphere at 1/100-size voxels, and batch
// queries (values() of 1e6 points) on one and two threads. Run:
//   ./build/shearbench_bench --benchmark_filter=MeshSdf
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "core/geometry/indenter.hpp"
#include "core/geometry/sdf.hpp"

namespace {

constexpr double kSphereRadius = 0.005;             // 10 mm sphere
constexpr double kVoxel = 2 * kSphereRadius / 100;  // 1/100 of its size: 0.1 mm

const sb::TriMesh& sphere_mesh() {
  static const sb::TriMesh mesh = sb::make_sphere_mesh(kSphereRadius, 5);  // 10,242 vertices
  return mesh;
}

sb::MeshSdfOptions options_with_band(double band_m) {
  sb::MeshSdfOptions o;
  o.voxel_size = kVoxel;
  o.band_width = band_m;
  return o;
}

// Arg: band width in millimetres.
void BM_MeshSdfBuild(benchmark::State& state) {
  const sb::MeshSdfOptions options = options_with_band(state.range(0) * 1e-3);
  for (auto _ : state) benchmark::DoNotOptimize(sb::make_mesh_sdf(sphere_mesh(), options));
  state.SetLabel(std::to_string(sphere_mesh().vertices.size()) + " vertices, voxel 0.1 mm");
}
BENCHMARK(BM_MeshSdfBuild)->Arg(1)->Arg(4)->Unit(benchmark::kMillisecond)->UseRealTime();

// 1e6 points uniform in the sphere's bounding box grown by 1 mm, per thread, one values() call each.
void BM_MeshSdfQuery(benchmark::State& state) {
  static const sb::SdfPtr sdf = sb::make_mesh_sdf(sphere_mesh(), options_with_band(0.004));
  std::mt19937 rng(static_cast<unsigned>(state.thread_index()) + 1);
  std::uniform_real_distribution<double> u(-kSphereRadius - 0.001, kSphereRadius + 0.001);
  std::vector<sb::Vec3> p(1'000'000);
  for (auto& q : p) q = sb::Vec3(u(rng), u(rng), u(rng));
  std::vector<double> phi(p.size());
  for (auto _ : state) {
    sdf->values(p, phi);
    benchmark::DoNotOptimize(phi.data());
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * p.size()));
}
BENCHMARK(BM_MeshSdfQuery)->Threads(1)->Threads(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
