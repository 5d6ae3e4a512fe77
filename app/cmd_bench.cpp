// `shearbench bench --model M --envs N --steps S [--repeat R] [--profile] [--json OUT]`: the benchmark
// workload of BENCH_WORKLOAD.md (peg grasp, 2 pads per env), timed per batched step (core/api/bench_run,
// which steps the public API's SensorModel).
// Prints a table (median / min / max ms per batched step over k = 3..S-1, sensor-steps per second) and,
// with --profile, the CPU time per phase from a separate, instrumented run.
#include <tbb/global_control.h>

#include <cstdio>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "app/command.hpp"
#include "core/api/bench_run.hpp"
#include "core/base/atomic_write.hpp"
#include "core/base/error.hpp"
#include "core/calibration/param_sets.hpp"
#include "core/data/tsd.hpp"
#include "core/models/bench_workload.hpp"
#include "core/models/model.hpp"

namespace sb::app {
namespace {

struct BenchArgs {
  std::string model = "all";
  std::vector<int> envs;  // empty: 256, 512, 1024
  int steps = kBenchDefaultSteps;
  int repeat = 1;
  bool profile = false;
  std::string json_out;
  std::string field_out;  // the last step's field of the one case run (--field-out)
};

// The 1-, 5- and 15-minute load averages, to record how busy the machine was.
std::array<double, 3> load_average() {
  std::array<double, 3> l{-1, -1, -1};
  std::ifstream in("/proc/loadavg");
  in >> l[0] >> l[1] >> l[2];
  return l;
}

struct Measured {
  BenchResult best;                 // the repeat with the lowest median
  std::vector<double> run_medians;  // every repeat's median
  std::optional<BenchResult> profile;
};

// The field of the last step, for a consumer of the API to compare its own with (shearbench::bench_poses).
void write_field(const BenchWorkload& w, const BenchArgs& a) {
  const nlohmann::json doc = {{"workload", "BENCH_WORKLOAD.md"},
                              {"model", w.model()},
                              {"param_set", kPublishedParamSet},
                              {"envs", w.envs()},
                              {"steps", a.steps},
                              {"shape", {w.envs() * kBenchSensors, -1, 2}},
                              {"field_px", w.last_field()}};
  write_file_atomic(a.field_out, doc.dump() + "\n");
}

Measured measure(const std::string& model, int envs, const BenchArgs& a) {
  BenchWorkload w(model, envs, a.steps);
  Measured m;
  for (int r = 0; r < a.repeat; ++r) {
    BenchResult res = w.run(false);
    m.run_medians.push_back(res.median_ms);
    if (r == 0 || res.median_ms < m.best.median_ms) m.best = std::move(res);
  }
  if (!a.field_out.empty()) write_field(w, a);
  if (a.profile) m.profile = w.run(true);
  return m;
}

nlohmann::json to_json(const Measured& m) {
  const BenchResult& r = m.best;
  nlohmann::json j = {{"model", r.model},
                      {"envs", r.envs},
                      {"slots", r.slots},
                      {"median_ms", r.median_ms},
                      {"min_ms", r.min_ms},
                      {"max_ms", r.max_ms},
                      {"sensor_steps_per_s", r.sensor_steps_per_s},
                      {"step_ms", r.step_ms},
                      {"repeat_median_ms", m.run_medians},
                      {"checksum_px", r.checksum}};
  if (m.profile) {
    nlohmann::json p = nlohmann::json::object();
    for (int i = 0; i < kPhaseCount; ++i) p[phase_name(static_cast<Phase>(i))] = m.profile->phase_cpu_ms[i];
    j["profile_cpu_ms_per_step"] = p;
    j["profile_median_ms"] = m.profile->median_ms;
  }
  return j;
}

void print_profile(const BenchResult& p) {
  double total = 0;
  for (double v : p.phase_cpu_ms) total += v;
  std::printf("    profile (instrumented run, median %.3f ms; CPU ms per step summed over threads):", p.median_ms);
  for (int i = 0; i < kPhaseCount; ++i)
    std::printf(" %s %.3f (%.0f%%)%s", phase_name(static_cast<Phase>(i)), p.phase_cpu_ms[i],
                total > 0 ? 100 * p.phase_cpu_ms[i] / total : 0.0, i + 1 < kPhaseCount ? "," : "\n");
}

int run_bench(const BenchArgs& a, const GlobalOptions& g) {
  std::unique_ptr<tbb::global_control> limit;
  if (g.threads > 0)
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, g.threads);
  std::vector<std::string> models;
  if (a.model == "all") {
    models = bench_model_ids();
  } else {
    bool known = false;
    for (const auto& id : bench_model_ids()) known = known || id == a.model;
    if (!known) throw InputError("--model", "unknown model '" + a.model + "' (" + model_ids_text(", ") + ", all)");
    models = {a.model};
  }
  const std::vector<int> envs = a.envs.empty() ? std::vector<int>{256, 512, 1024} : a.envs;
  if (a.repeat < 1) throw std::invalid_argument("bench: --repeat must be >= 1");
  if (!a.field_out.empty() && (models.size() != 1 || envs.size() != 1))
    throw InputError("--field-out", "needs one --model and one --envs (the field of one case)");
  const auto load_before = load_average();
  std::printf(
      "BENCH_WORKLOAD: peg grasp, 2 pads per env, steps 0..%d, timed k = %d..%d (median/min/max of %d), "
      "threads %zu, load average %.2f %.2f %.2f\n",
      a.steps - 1, kBenchWarmupSteps, a.steps - 1, a.steps - kBenchWarmupSteps,
      tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism), load_before[0], load_before[1],
      load_before[2]);
  std::printf("%-17s %6s %6s %11s %9s %9s %16s\n", "model", "envs", "slots", "median ms", "min ms", "max ms",
              "sensor-steps/s");
  nlohmann::json results = nlohmann::json::array();
  for (const auto& model : models)
    for (int n : envs) {
      const Measured m = measure(model, n, a);
      const BenchResult& r = m.best;
      std::printf("%-17s %6d %6d %11.3f %9.3f %9.3f %16.4g\n", model.c_str(), r.envs, r.slots, r.median_ms, r.min_ms,
                  r.max_ms, r.sensor_steps_per_s);
      if (a.repeat > 1) {
        std::printf("    medians of the %d repeats:", a.repeat);
        for (double v : m.run_medians) std::printf(" %.3f", v);
        std::printf("\n");
      }
      if (m.profile) print_profile(*m.profile);
      std::fflush(stdout);
      results.push_back(to_json(m));
    }
  if (!a.json_out.empty()) {
    const auto load_after = load_average();
    nlohmann::json doc = {{"workload", "BENCH_WORKLOAD.md"},
                          {"steps", a.steps},
                          {"warmup_steps", kBenchWarmupSteps},
                          {"dt_s", kBenchDt},
                          {"threads", tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism)},
                          {"repeat", a.repeat},
                          {"load_average_before", load_before},
                          {"load_average_after", load_after},
                          {"results", results}};
    write_file_atomic(a.json_out, doc.dump(2) + "\n");
    std::printf("wrote %s\n", a.json_out.c_str());
  }
  return 0;
}

void add_flags(CLI::App& sub, BenchArgs& a) {
  sub.add_option("--model", a.model, model_ids_text() + " | all")->capture_default_str();
  sub.add_option("--envs", a.envs, "environments (2 sensors each); repeatable; default 256 512 1024")
      ->check(CLI::PositiveNumber);
  sub.add_option("--steps", a.steps,
                 "steps run, k = 0..S-1 (4..50); k = 0..2 are warm-up, statistics over k = 3..S-1; "
                 "23 is the workload's definition, more adds the later hold/slide steps")
      ->check(CLI::Range(kBenchWarmupSteps + 1, kBenchMaxSteps))
      ->capture_default_str();
  sub.add_option("--repeat", a.repeat, "run each case R times and report the run with the lowest median")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  sub.add_flag("--profile", a.profile, "add an instrumented run: CPU time per phase");
  sub.add_option("--json", a.json_out, "write the results as JSON (atomically)");
  sub.add_option("--field-out", a.field_out,
                 "write the last step's field as JSON, field_px [slot][marker][2] (slot = env * 2 + pad), to compare "
                 "a consumer of the library with (one --model and one --envs)");
}

const Subcommand<BenchArgs> kBenchCommand{
    "bench", "time the shear models on the BENCH_WORKLOAD peg grasp (ms per batched step)", 80, add_flags, run_bench};

}  // namespace
}  // namespace sb::app
