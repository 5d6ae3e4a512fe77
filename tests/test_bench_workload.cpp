#include <catch2/catch.hpp>
#include <cmath>

#include "core/models/bench_workload.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_bench_workload {

using namespace sb;

namespace {
constexpr double kGeomTol = 1e-12;  // metres: exact arithmetic on mm-sized numbers
}

TEST_CASE("splitmix64 is the standard generator", "[bench]") {
  // The first output of the reference splitmix64 seeded with 0 is 0xE220A8397B1DCDAF.
  CHECK(splitmix64(0) == 0xE220A8397B1DCDAFull);
  const double u = bench_uniform(20260311, 3, 5);
  CHECK(u >= 0.0);
  CHECK(u < 1.0);
}

TEST_CASE("the peg has the 1992 surface points of the workload", "[bench]") {
  // Side: 34 x 53 = 1802. Each cap: 1 + 6 + 13 + 19 + 25 + 31 = 95. Total 1802 + 190 = 1992.
  const SurfaceSamples s = bench_peg_points();
  REQUIRE(s.p_IS.size() == 1992);
  // Cap order: side rings first, then the z = -L/2 cap centre.
  CHECK((s.p_IS[1802] - Vec3(0, 0, -kPegLength / 2)).norm() < kGeomTol);
  CHECK((s.p_IS[1802 + 95] - Vec3(0, 0, kPegLength / 2)).norm() < kGeomTol);
  // Every side point is on the cylinder of radius R.
  for (int i = 0; i < 1802; ++i) CHECK(std::abs(std::hypot(s.p_IS[i].x(), s.p_IS[i].y()) - kPegRadius) < kGeomTol);
}

TEST_CASE("the peg presses each pad by exactly the drawn depth at step 10", "[bench]") {
  // At k = 10 the pads have closed by delta = d. In the authors' frame the peg surface reaches
  // z_A = delta; our E is Rx(pi) of it, so the lowest point is at z_E = -d. Yaw and twist are about the
  // pad normal (world y), so they do not change the extent along it; odd side rings have a point exactly
  // facing each pad (angle 3*pi/2 = 2*pi*25.5/34).
  BenchWorkloadSpec spec;
  spec.envs = 4;
  spec.steps = 12;
  const auto X = bench_trajectory(spec);
  const SurfaceSamples s = bench_peg_points();
  for (int e = 0; e < spec.envs; ++e) {
    const double d = bench_env_params(spec.seed, e).press_depth_m;
    for (int sensor = 0; sensor < kBenchSensors; ++sensor) {
      double min_z = 1e9;
      for (const Vec3& p : s.p_IS) min_z = std::min(min_z, (X[10][e * kBenchSensors + sensor] * p).z());
      CHECK(std::abs(min_z + d) < kGeomTol);
      // At k = 0 the pads are 0.2 mm away.
      double min_z0 = 1e9;
      for (const Vec3& p : s.p_IS) min_z0 = std::min(min_z0, (X[0][e * kBenchSensors + sensor] * p).z());
      CHECK(std::abs(min_z0 - 0.2e-3) < kGeomTol);
    }
  }
}

}  // namespace test_bench_workload
