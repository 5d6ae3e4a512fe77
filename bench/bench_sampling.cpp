// Indenter surface sampling: Poisson-disk samples of the cow mesh (data root meshes/cow.obj, scaled to
// 6 cm) at HydroShear's 0.75 mm spacing, ~4000 points; what opening a mesh indenter costs on top of its
// SDF. Its budget (under a second on one core) is read here, not asserted in a unit test. Run:
//   ./build/shearbench_bench --benchmark_filter=PoissonDisk
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>

#include "core/base/data_root.hpp"
#include "core/geometry/indenter.hpp"
#include "core/geometry/mesh.hpp"

namespace {

void BM_PoissonDiskCow(benchmark::State& state) {
  const char* env = std::getenv("SHEARBENCH_DATA");
  const std::string root = env && *env ? env : sb::resolve_data_root();
  sb::MeshLoadOptions opt;
  opt.scale = 0.06 / 10.4;  // meshes/SOURCE.md: about 10.4 units long
  const sb::TriMesh cow = sb::load_mesh((std::filesystem::path(root) / "meshes/cow.obj").string(), opt);
  std::size_t points = 0;
  for (auto _ : state) {
    const sb::SurfaceSamples s = sb::poisson_disk_samples(cow, 0.75e-3);
    points = s.p_IS.size();
    benchmark::DoNotOptimize(points);
  }
  state.SetLabel(std::to_string(points) + " points at 0.75 mm");
}
BENCHMARK(BM_PoissonDiskCow)->Unit(benchmark::kMillisecond);

}  // namespace
