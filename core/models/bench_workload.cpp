#include "core/models/bench_workload.hpp"

#include <algorithm>
#include <cmath>

namespace sb {

std::uint64_t splitmix64(std::uint64_t x) {
  std::uint64_t z = x + 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

double bench_uniform(std::uint64_t seed, int env, int c) {
  const std::uint64_t bits =
      splitmix64(seed + 16ull * static_cast<std::uint64_t>(env) + static_cast<std::uint64_t>(c)) >> 11;
  return static_cast<double>(bits) * 0x1.0p-53;
}

SurfaceSamples bench_peg_points() {
  const double R = kPegRadius, L = kPegLength, h = kPegPointSpacing;
  const int n_theta = static_cast<int>(std::lround(2 * M_PI * R / h));  // 34
  const int n_z = static_cast<int>(std::lround(L / h));                 // 53
  SurfaceSamples s;
  for (int k = 0; k < n_z; ++k) {
    const double z = -L / 2 + (k + 0.5) * L / n_z;
    for (int i = 0; i < n_theta; ++i) {
      const double a = 2 * M_PI * (i + 0.5 * (k % 2)) / n_theta;
      const Vec3 radial(std::cos(a), std::sin(a), 0);
      s.p_IS.push_back(R * radial + Vec3(0, 0, z));
      s.n_IS.push_back(radial);
    }
  }
  for (const double side : {-1.0, 1.0}) {
    const double z = side * L / 2;
    s.p_IS.emplace_back(0, 0, z);
    s.n_IS.emplace_back(0, 0, side);
    for (int j = 1; j * h < R; ++j) {
      const int n = static_cast<int>(std::lround(2 * M_PI * j * h / h));
      for (int i = 0; i < n; ++i) {
        const double a = 2 * M_PI * i / n;
        s.p_IS.emplace_back(j * h * std::cos(a), j * h * std::sin(a), z);
        s.n_IS.emplace_back(0, 0, side);
      }
    }
  }
  const double area = 2 * M_PI * R * L + 2 * M_PI * R * R;
  s.area_m2.assign(s.p_IS.size(), area / static_cast<double>(s.p_IS.size()));
  return s;
}

BenchEnvParams bench_env_params(std::uint64_t seed, int env) {
  auto u = [&](int c) { return bench_uniform(seed, env, c); };
  const double deg = M_PI / 180;
  return {0.5e-3 + 0.5e-3 * u(0), 2.0e-3 * u(1),           2 * M_PI * u(2),         10 * deg * (2 * u(3) - 1),
          3e-3 * (2 * u(4) - 1),  1.5e-3 * (2 * u(5) - 1), 5 * deg * (2 * u(6) - 1)};
}

namespace {

// Pad pose in the world, authors' frame A: rotation columns (x_A, y_A, z_A) and position.
Pose pad_pose_W(int sensor, double delta) {
  Mat3 R;
  const double side = sensor == 0 ? -1.0 : 1.0;  // left pad at -y, right pad at +y
  R.col(0) = Vec3(0, 0, 1);
  R.col(1) = Vec3(side, 0, 0);
  R.col(2) = Vec3(0, side, 0);
  Pose X = Pose::Identity();
  X.linear() = R;
  X.translation() = Vec3(0, side * (kPegRadius - delta), 0);
  return X;
}

}  // namespace

std::vector<std::vector<Pose>> bench_trajectory(const BenchWorkloadSpec& spec) {
  Pose X_EA = Pose::Identity();
  X_EA.linear() = Rx(M_PI);
  std::vector<BenchEnvParams> env(spec.envs);
  for (int e = 0; e < spec.envs; ++e) env[e] = bench_env_params(spec.seed, e);
  std::vector<std::vector<Pose>> out(spec.steps, std::vector<Pose>(spec.envs * kBenchSensors));
  for (int k = 0; k < spec.steps; ++k) {
    const double press = std::min(k / 10.0, 1.0);
    const double sigma = std::clamp((k - 10) / 39.0, 0.0, 1.0);
    for (int e = 0; e < spec.envs; ++e) {
      const BenchEnvParams& q = env[e];
      const double delta = -0.2e-3 + (q.press_depth_m + 0.2e-3) * press;
      Pose X_WI = Pose::Identity();
      X_WI.linear() = Ry(q.yaw0_rad + sigma * q.twist_rad);
      X_WI.translation() = Vec3(q.offset_x_m + sigma * q.slide_m * std::cos(q.slide_dir_rad), 0,
                                q.offset_z_m + sigma * q.slide_m * std::sin(q.slide_dir_rad));
      for (int s = 0; s < kBenchSensors; ++s)
        out[k][e * kBenchSensors + s] = X_EA * pad_pose_W(s, delta).inverse() * X_WI;
    }
  }
  return out;
}

}  // namespace sb
