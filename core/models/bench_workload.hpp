#pragma once
// The HydroShear benchmark workload (../shared/docs/BENCH_WORKLOAD.md), generated exactly: a capped
// cylinder peg (R 4 mm, L 40 mm) grasped between two flat GelSight-Mini pads, per-env random press,
// slide, twist and offsets from splitmix64, 50 steps.
//
// Frames. The workload is specified in the authors' elastomer frame A (gel 0 <= z_A <= 4.5 mm, pressing
// toward +z_A). Our E is tsd/1's (gel z_E <= 0, +z_E out of the gel). We map with the proper rotation
// X_EA = Rx(pi) (x_E = x_A, y_E = -y_A, z_E = -z_A) rather than a z-mirror, which is not a rigid motion;
// the 7 x 9 marker grid is symmetric under y -> -y, so the marker set is the same.
#include <cstdint>
#include <vector>

#include "core/geometry/indenter.hpp"
#include "core/geometry/pose.hpp"

namespace sb {

struct BenchWorkloadSpec {
  int envs = 1024;
  int steps = 50;
  std::uint64_t seed = 20260311;
};

inline constexpr int kBenchSensors = 2;  // left pad, right pad
inline constexpr double kPegRadius = 0.004;
inline constexpr double kPegLength = 0.040;
inline constexpr double kPegPointSpacing = 0.75e-3;

std::uint64_t splitmix64(std::uint64_t x);
// u_{e,c} in [0, 1): (splitmix64(seed + 16 e + c) >> 11) * 2^-53.
double bench_uniform(std::uint64_t seed, int env, int c);

// The deterministic P = 1992 peg surface points (side rings, then the -L/2 cap, then the +L/2 cap),
// with outward normals and equal shares of the surface area.
SurfaceSamples bench_peg_points();

struct BenchEnvParams {
  double press_depth_m, slide_m, slide_dir_rad, twist_rad, offset_z_m, offset_x_m, yaw0_rad;
};
BenchEnvParams bench_env_params(std::uint64_t seed, int env);

// X_EI for every step, env and sensor: index [step][env * kBenchSensors + sensor], in our E frame.
std::vector<std::vector<Pose>> bench_trajectory(const BenchWorkloadSpec& spec);

}  // namespace sb
