#pragma once
// The timing loop of the benchmark workload (../shared/docs/BENCH_WORKLOAD.md), shared by
// `shearbench bench` (app/cmd_bench.cpp) and the Google Benchmark cases (bench/bench_models.cpp), stepping the
// public API's SensorModel (include/shearbench/sensor_model.hpp) with the poses shearbench::bench_poses gives.
//
// Timed quantity: one batched step for all E envs and both sensors (2E slots): the API's pose conversion, the
// transforms, both SDF lookups, the state step, the shear sum and the dilation. The poses of every step are generated
// before any timing; the step runs without diagnostics into a preallocated output. Steps k = 0..2 are
// warm-up; the statistics are over k = 3..S-1 with the state carried from k = 0 (S = 23 is the
// workload's definition, k = 3..22; a larger S, up to the trajectory's 50 steps, adds the later hold
// and slide steps to the statistics).
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "core/models/phase_profile.hpp"

namespace sb {

inline constexpr int kBenchWarmupSteps = 3;
inline constexpr int kBenchDefaultSteps = 23;  // k = 0..22
inline constexpr int kBenchMaxSteps = 50;      // the workload's trajectory length
inline constexpr double kBenchDt = 1.0 / 60;   // s between steps (TacSL's velocities; 60 Hz control)

// hydroshear, fots, fots-reimpl, tacsl, tacsl-normalized.
const std::vector<std::string>& bench_model_ids();

struct BenchResult {
  std::string model;
  int envs = 0, slots = 0, steps = 0, timed_steps = 0, threads = 0;
  std::vector<double> step_ms;                   // wall time of every step k = 0..steps-1
  double median_ms = 0, min_ms = 0, max_ms = 0;  // over k = 3..steps-1
  double sensor_steps_per_s = 0;                 // slots / median step time
  bool profiled = false;
  // Profile mode: CPU milliseconds per timed step spent in each phase, summed over worker threads
  // (so they add up to about threads x wall time when all cores are busy).
  std::array<double, kPhaseCount> phase_cpu_ms{};
  double checksum = 0;  // sum of |disp| over every marker of the last step
};

// One prepared workload: trajectory, sensor, peg and the model's batch of 2E slots.
class BenchWorkload {
 public:
  // Throws std::invalid_argument for an unknown model, envs < 1, or steps outside 4..50.
  BenchWorkload(const std::string& model, int envs, int steps = kBenchDefaultSteps);
  ~BenchWorkload();
  BenchWorkload(BenchWorkload&&) noexcept;
  // Resets the batch and runs every step; profile = true adds the phase timers (which cost a little).
  BenchResult run(bool profile = false);
  const std::string& model() const { return model_; }
  // The field of the last step run, [slot][marker][2] in pixels (slot = env * 2 + pad); zeros before a run.
  const std::vector<double>& last_field() const;
  int envs() const { return envs_; }

 private:
  struct Impl;
  std::string model_;
  int envs_, steps_;
  std::unique_ptr<Impl> impl_;
};

// The median, min and max of values (non-empty); the median of an even count is the mean of the two
// middle values.
struct Stats {
  double median, min, max;
};
Stats bench_stats(std::vector<double> values);

}  // namespace sb
