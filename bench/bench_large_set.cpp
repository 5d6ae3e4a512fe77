// The residual loop and `evaluate` at the size real collections come in (docs/performance.md, "Large sets"): a set of
// N samples made from the shipped TacTip set (core/loop/synthetic_set.hpp: every sample's path jittered, the field of
// the loop's answer for this sensor at the jittered path plus the sample's own residual against it plus 0.1 px of
// tracker noise; the first copy of each sample keeps its pose). N = 500 takes 250 + 250 evenly spaced samples of the
// shipped set as they are; N = 2000 is the shipped set (1999) and one copy; N = 10,000 five copies of each.
// The loop runs as docs/residuals/run_real.sh runs it on the shipped set (HydroShear from the shipped set's values,
// its model-form round, the default candidates, three rounds, at most 10 steps per stage; past 2000 samples the search
// sees a search set of 2000 and the answer is refitted and scored on all: ResidualOptions::search_set). Goal at
// 10,000 samples: 20 min and 8 GB on 2 cores. Peak memory is the process's (getrusage): run one size per process,
//   ./build/shearbench_bench --benchmark_filter='BM_LargeSetLoop/10000'
// Needs the data root ($SHEARBENCH_DATA or ../shared/data).
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <algorithm>
#include <string>

#include "bench/tactip_data.hpp"
#include "core/calibration/param_sets.hpp"
#include "core/data/json_read.hpp"
#include "core/effects/model_spec.hpp"
#include "core/loop/residual.hpp"
#include "core/loop/synthetic_set.hpp"

namespace {

// The loop's answer on the shipped set, as its report wrote it (docs/residuals/real_tactip_full_hydroshear).
const char* const kAnswer = "hydroshear+dome_sway+tool_frame+skin_indentation";

double peak_rss_gb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / (1024.0 * 1024.0);  // ru_maxrss is in KiB on Linux
}

sb::ParamSet answer_params() {
  const std::string file = std::string(SHEARBENCH_SOURCE_DIR) +
                           "/docs/residuals/real_tactip_full_hydroshear/report_params.json";
  sb::ParamSet p = sb::load_param_set("tactip_shear").params(kAnswer);
  p.update_from_json(sb::jsonin::load_file(file).at(kAnswer), file);
  return p;
}

// The shipped samples the set is made from: every one, or `n` / 2 of each split evenly spaced when n is smaller.
std::vector<sb::FitSample> source_samples(std::size_t n) {
  const auto& cal = shearbench_bench::tactip_calibration().samples;
  const auto& val = shearbench_bench::tactip_validation();
  std::vector<sb::FitSample> out;
  if (n >= cal.size() + val.size()) {
    out = cal;
    out.insert(out.end(), val.begin(), val.end());
    return out;
  }
  out = sb::subset(cal, sb::evenly_spaced(cal.size(), n / 2));
  const auto v = sb::subset(val, sb::evenly_spaced(val.size(), n - n / 2));
  out.insert(out.end(), v.begin(), v.end());
  return out;
}

sb::ResidualInputs large_set(std::size_t n) {
  const auto sensor = shearbench_bench::tactip_calibration().sensor;
  const auto source = source_samples(n);
  sb::SyntheticSetOptions o;
  o.samples = std::max(n, source.size());
  auto made = sb::synthetic_samples(source, sb::spec_model_factory(kAnswer, sensor), answer_params(), o);
  sb::ResidualInputs in;
  in.dataset = "tactip_shear x" + std::to_string(made.size());
  in.model_id = "hydroshear";
  in.sensor = sensor;
  for (auto& s : made) (s.split == "calibration" ? in.calibration : in.validation).push_back(std::move(s));
  in.base_params = sb::load_param_set("tactip_shear").params("hydroshear");
  return in;
}

void BM_LargeSetLoop(benchmark::State& state) {
  const sb::ResidualInputs in = large_set(static_cast<std::size_t>(state.range(0)));
  sb::ResidualOptions o;
  o.max_iterations = 10;
  o.selection.max_effects = 3;
  for (auto _ : state) {
    const sb::ResidualReport r = sb::run_residual_loop(in, o);
    state.SetLabel(r.after_model);
    state.counters["validation_rmse_px"] = r.after.validation.overall.result().rmse_px;
    state.counters["before_rmse_px"] = r.before.validation.overall.result().rmse_px;
  }
  state.counters["samples"] = static_cast<double>(in.calibration.size() + in.validation.size());
  state.counters["peak_rss_gb"] = peak_rss_gb();
}
BENCHMARK(BM_LargeSetLoop)->Arg(500)->Arg(2000)->Arg(10000)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

// The answer scored on every sample of the set, as `evaluate` and the loop's scores run it.
void BM_LargeSetEvaluate(benchmark::State& state) {
  const sb::ResidualInputs in = large_set(static_cast<std::size_t>(state.range(0)));
  const sb::ParamSet p = answer_params();
  for (auto _ : state) {
    benchmark::DoNotOptimize(sb::fit_rmse_px(kAnswer, in.sensor, in.validation, p));
    benchmark::DoNotOptimize(sb::fit_rmse_px(kAnswer, in.sensor, in.calibration, p));
  }
  state.counters["samples"] = static_cast<double>(in.calibration.size() + in.validation.size());
  state.counters["peak_rss_gb"] = peak_rss_gb();
}
BENCHMARK(BM_LargeSetEvaluate)->Arg(10000)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

}  // namespace
