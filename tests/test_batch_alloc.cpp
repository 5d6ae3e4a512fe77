// The batched models allocate nothing on the heap per step once warm ("no heap allocation per
// step"): every operator new of the process is counted while the batch steps along the benchmark
// trajectory a second time after a reset.
#include <catch2/catch.hpp>

#include <atomic>
#include <cstdlib>
#include <new>

#include <tbb/task_arena.h>

#include "core/effects/effects.hpp"
#include "core/geometry/sdf.hpp"
#include "core/models/bench_workload.hpp"
#include "core/models/fots.hpp"
#include "core/models/hydroshear.hpp"
#include "core/models/model.hpp"
#include "core/models/tacsl.hpp"
#include "core/sensor/sensor.hpp"
#include "tests/asan_detect.hpp"

// Everything up to the test cases counts allocations: none of it exists under AddressSanitizer, which
// supplies its own operator new (the release pass runs these tests; the sanitizer pass skips them).
#ifndef SB_TEST_ASAN
namespace {
std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0};
std::atomic<long> g_bytes{0};
}  // namespace

// The replacement allocator counts while g_counting is set.
void* operator new(std::size_t n) {
  if (g_counting.load(std::memory_order_relaxed)) {
    g_allocations.fetch_add(1, std::memory_order_relaxed);
    g_bytes.fetch_add(static_cast<long>(n), std::memory_order_relaxed);
  }
  if (void* p = std::malloc(n == 0 ? 1 : n)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) { return ::operator new(n); }
void* operator new(std::size_t n, std::align_val_t a) {
  if (g_counting.load(std::memory_order_relaxed)) {
    g_allocations.fetch_add(1, std::memory_order_relaxed);
    g_bytes.fetch_add(static_cast<long>(n), std::memory_order_relaxed);
  }
  const std::size_t align = static_cast<std::size_t>(a);
  if (void* p = std::aligned_alloc(align, (n + align - 1) / align * align)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n, std::align_val_t a) { return ::operator new(n, a); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }

namespace {

using namespace sb;

// Steps `batch` along every step of `X_EI` (the benchmark's [step][slot] poses); returns the number of
// operator new calls made during the steps.
template <class Batch>
long allocations_along(Batch& batch, const std::vector<std::vector<Pose>>& X_EI, std::vector<Vec2>& disp) {
  g_allocations = 0;
  g_counting = true;
  for (const auto& poses : X_EI) batch.step(poses, 1.0 / 60, disp, {});
  g_counting = false;
  return g_allocations.load();
}

// First pass warms every buffer (state columns, scratch); after reset() the same trajectory must not
// allocate. One thread: with more, which worker first touches a per-thread scratch depends on scheduling.
template <class Batch>
long second_pass_allocations(Batch batch, int slots, std::size_t markers) {
  BenchWorkloadSpec spec;
  spec.envs = slots / kBenchSensors;
  spec.steps = 50;
  const auto X_EI = bench_trajectory(spec);
  std::vector<Vec2> disp(static_cast<std::size_t>(slots) * markers, Vec2::Zero());
  long counted = -1;
  tbb::task_arena one(1);
  one.execute([&] {
    allocations_along(batch, X_EI, disp);
    batch.reset();
    counted = allocations_along(batch, X_EI, disp);
  });
  double largest = 0;
  for (const Vec2& d : disp) largest = std::max(largest, d.norm());
  CHECK(largest > 0.1);  // the peg is in contact at the end: the steps did work
  return counted;
}

// The benchmark's peg, its surface sampled `copies` times over (the same surface, copies times the points).
std::shared_ptr<Indenter> bench_peg(int copies = 1) {
  auto peg = std::make_shared<Indenter>();
  peg->name = "bench_peg";
  peg->sdf = make_capped_cylinder_sdf(kPegRadius, kPegLength);
  const SurfaceSamples one = bench_peg_points();
  for (int c = 0; c < copies; ++c) {
    peg->samples.p_IS.insert(peg->samples.p_IS.end(), one.p_IS.begin(), one.p_IS.end());
    peg->samples.n_IS.insert(peg->samples.n_IS.end(), one.n_IS.begin(), one.n_IS.end());
  }
  return peg;
}

// Bytes operator new hands out while `model` is cloned.
long clone_bytes_of(const ShearModel& model) {
  g_bytes = 0;
  g_counting = true;
  auto copy = model.clone();
  g_counting = false;
  return g_bytes.load();
}

}  // namespace
#endif  // SB_TEST_ASAN

TEST_CASE("the batched models allocate nothing per step once warm", "[models][alloc]") {
#ifdef SB_TEST_ASAN
  WARN("skipped: AddressSanitizer replaces operator new; the release pass runs this test");
#else
  constexpr int kEnvs = 4;
  constexpr int kSlots = kEnvs * kBenchSensors;
  auto sensor = std::make_shared<const Sensor>(make_default_sensor());
  const auto peg = bench_peg();
  const std::size_t markers = sensor->p_EM.size();

  // Sanity of the counter itself: a vector that grows is seen.
  g_allocations = 0;
  g_counting = true;
  { std::vector<int> v(100); }
  g_counting = false;
  REQUIRE(g_allocations.load() == 1);

  SECTION("hydroshear") {
    CHECK(second_pass_allocations(HydroShearBatch(sensor, peg, kSlots, default_params("hydroshear")), kSlots,
                                  markers) == 0);
  }
  SECTION("fots") {
    CHECK(second_pass_allocations(FotsBatch(FotsVariant::kOriginal, sensor, peg, kSlots, default_params("fots")),
                                  kSlots, markers) == 0);
  }
  SECTION("fots-reimpl") {
    CHECK(second_pass_allocations(FotsBatch(FotsVariant::kReimpl, sensor, peg, kSlots, default_params("fots-reimpl")),
                                  kSlots, markers) == 0);
  }
  SECTION("tacsl") {
    CHECK(second_pass_allocations(TacslBatch(false, sensor, peg, kSlots, default_params("tacsl")), kSlots, markers) ==
          0);
  }
  SECTION("tacsl-normalized") {
    CHECK(second_pass_allocations(TacslBatch(true, sensor, peg, kSlots, default_params("tacsl-normalized")), kSlots,
                                  markers) == 0);
  }
#endif
}

// The workbench clones every model every 16 steps (AppState's checkpoints, for seeks), for the whole length of
// the user's path. A clone must copy the state (O(contact)), not what was built once from the indenter: with
// the point tables copied, the hour's soak grew with the path (docs/reliability.md). So a clone of HydroShear
// out of contact costs the same bytes whether its indenter has n or 4n points.
TEST_CASE("a HydroShear clone (a workbench checkpoint) does not copy the indenter's point tables", "[models][alloc]") {
#ifdef SB_TEST_ASAN
  WARN("skipped: AddressSanitizer replaces operator new; the release pass runs this test");
#else
  auto sensor = std::make_shared<const Sensor>(make_default_sensor());
  const auto clone_bytes = [&](int copies) {
    return clone_bytes_of(*make_model("hydroshear", sensor, bench_peg(copies)));
  };
  const long n = clone_bytes(1), n4 = clone_bytes(4);
  INFO("clone bytes: " << n << " with the peg's points, " << n4 << " with 4 times as many ("
                       << bench_peg_points().p_IS.size() << " points)");
  CHECK(n4 == n);
#endif
}

// The same for a model with effects (a residual analysis opened in the workbench): its clone must not carry
// anything that grows with the steps taken (the per-step penetration cache did: O(path) per checkpoint).
TEST_CASE("an effect-wrapped model's clone costs the same after 10 steps as after 200", "[models][alloc]") {
#ifdef SB_TEST_ASAN
  WARN("skipped: AddressSanitizer replaces operator new; the release pass runs this test");
#else
  auto sensor = std::make_shared<const Sensor>(make_default_sensor());
  const auto peg = bench_peg();
  const auto clone_bytes_after = [&](int steps) {
    auto model = wrap_with_effects(make_model("hydroshear", sensor, peg), {"viscoelastic_creep", "lens_distortion"},
                                   sensor, peg);
    Pose X_EI = Pose::Identity();
    X_EI.translation() = Vec3(0, 0, 0.01);  // 1 cm above the gel: every step is out of contact
    FieldOutput out;
    for (int k = 0; k < steps; ++k) model->step(X_EI, 0.01, &out);
    return clone_bytes_of(*model);
  };
  const long after10 = clone_bytes_after(10), after200 = clone_bytes_after(200);
  INFO("clone bytes after 10 steps " << after10 << ", after 200 steps " << after200);
  CHECK(after200 == after10);
#endif
}
