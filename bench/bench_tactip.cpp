// The real TacTip path (the goals: each model fitted on the whole calibration split within 5 min on 2
// cores): one sample's steps (the press, the slide, the one scored frame), a whole-split evaluation, and the
// fit of every model as `params --rebuild --set tactip_shear` runs it (its stages, then the joint refinement,
// at most 10 iterations per stage), the fit of the loop's answer, and the whole loop with its model-form round.
// Needs the data root ($SHEARBENCH_DATA or ../shared/data); the import
// (about 45 s) is kept in $TMPDIR/shearbench_bench_tactip and reused.
// Run: ./build/shearbench_bench --benchmark_filter=Tactip
//      ./build/shearbench_bench --benchmark_filter='Tactip(Fit|Evaluate)' --benchmark_min_time=1x   (minutes)
//      ./build/shearbench_bench --benchmark_filter=TactipLoop   (11.4 min by the CLI on two idle cores)

#include <benchmark/benchmark.h>

#include <filesystem>
#include <memory>
#include <mutex>

#include "bench/tactip_data.hpp"
#include "core/base/data_root.hpp"
#include "core/calibration/fit.hpp"
#include "core/calibration/fit_data.hpp"
#include "core/calibration/param_sets.hpp"
#include "core/data/importers.hpp"
#include "core/data/tsd.hpp"
#include "core/effects/model_spec.hpp"
#include "core/loop/residual.hpp"
#include "tests/tactip_variant.hpp"

namespace {

namespace fs = std::filesystem;
using shearbench_bench::tactip_calibration;
using shearbench_bench::tactip_dataset;
using shearbench_bench::tactip_validation;

// One sample's whole path (frames 0..11: above, pressed, the slide; only the last is scored) under HydroShear.
void BM_TactipSamplePath(benchmark::State& state) {
  const sb::FitData& d = tactip_calibration();
  const sb::FitSample& s = d.samples.at(static_cast<std::size_t>(state.range(0)));
  auto model = sb::make_spec_model("hydroshear", d.sensor, s.indenter);
  for (auto _ : state) benchmark::DoNotOptimize(sb::simulate_sample(*model, s));
  state.SetLabel(s.id + " " + s.motion);
}
BENCHMARK(BM_TactipSamplePath)->Arg(0)->Arg(500)->Unit(benchmark::kMillisecond);

// The whole calibration split (1000 samples) at the start parameters: one fit evaluation.
void BM_TactipEvaluateSplit(benchmark::State& state, const std::string& id) {
  const sb::FitData& d = tactip_calibration();
  for (auto _ : state) benchmark::DoNotOptimize(sb::fit_rmse_px(id, d.sensor, d.samples, sb::model_spec_params(id)));
  state.counters["samples"] = static_cast<double>(d.samples.size());
}
BENCHMARK_CAPTURE(BM_TactipEvaluateSplit, hydroshear, std::string("hydroshear"))
    ->Unit(benchmark::kSecond)
    ->UseRealTime()
    ->Iterations(1);

// Each model's fit on the whole calibration split, as the shipped set's rebuild runs it. Goal: 300 s each.
void BM_TactipFit(benchmark::State& state, const std::string& id) {
  const sb::FitData& d = tactip_calibration();
  sb::FitOptions o;
  o.joint = true;
  o.max_iterations = 10;
  for (auto _ : state) {
    const sb::CalibrationResult r = sb::fit_model(id, d.sensor, d.samples, sb::model_spec_params(id), o);
    int runs = 0;
    for (const auto& st : r.stages) runs += st.evaluations;
    state.counters["model_runs"] = runs;
  }
  state.counters["samples"] = static_cast<double>(d.samples.size());
}
BENCHMARK_CAPTURE(BM_TactipFit, hydroshear, std::string("hydroshear"))
    ->Unit(benchmark::kSecond)
    ->UseRealTime()
    ->Iterations(1);
BENCHMARK_CAPTURE(BM_TactipFit, hydroshear_contact, std::string("hydroshear-contact"))
    ->Unit(benchmark::kSecond)
    ->UseRealTime()
    ->Iterations(1);
BENCHMARK_CAPTURE(BM_TactipFit, fots_reimpl, std::string("fots-reimpl"))
    ->Unit(benchmark::kSecond)
    ->UseRealTime()
    ->Iterations(1);
BENCHMARK_CAPTURE(BM_TactipFit, tacsl, std::string("tacsl"))->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);
// The model the loop answers with on this set (docs/residuals/real_tactip_full_hydroshear, the same effects in another
// order), from its defaults: the pose effects' columns rerun HydroShear, the field effects' replay its remembered field
// (BaseFieldMemo).
BENCHMARK_CAPTURE(BM_TactipFit, hydroshear_skin_indentation_dome_sway_tool_frame,
                  std::string("hydroshear+skin_indentation+dome_sway+tool_frame"))
    ->Unit(benchmark::kSecond)
    ->UseRealTime()
    ->Iterations(1);

// The whole residual loop as `shearbench residual --dataset <import> --model hydroshear --max-effects 3
// --max-iterations 10` runs it: HydroShear fitted from the shipped set's values, its model-form round, the default
// candidates in greedy rounds (the fits that rerun the form on 250 of the 1000 calibration samples:
// ResidualOptions::search_samples), the final joint refit on all, the residual structure. Goal: 20 min.
void BM_TactipLoop(benchmark::State& state) {
  sb::ResidualInputs in;
  in.dataset = "tactip_shear";
  in.model_id = "hydroshear";
  in.sensor = tactip_calibration().sensor;
  in.calibration = tactip_calibration().samples;
  in.validation = tactip_validation();
  in.base_params = sb::load_param_set("tactip_shear").params("hydroshear");
  sb::ResidualOptions o;
  o.max_iterations = 10;
  o.selection.max_effects = 3;
  for (auto _ : state) {
    const sb::ResidualReport r = sb::run_residual_loop(in, o);
    state.SetLabel(r.after_model);
    state.counters["validation_rmse_px"] = r.after.validation.overall.result().rmse_px;
  }
}
BENCHMARK(BM_TactipLoop)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

// A new TacTip from scratch, as the held-out second sensor would come (tests/tactip_variant.hpp): every row of the
// shipped set magnified 1.06, turned 17 deg and cropped to 445 x 440 px, no image_0.png, the depths 0.8 mm deeper
// with 12 presses short of the touch, sorted by depth, CSVs with CRLF and a BOM. Imported with nothing told, the
// base fitted from the shipped set's values and the whole loop run as BM_TactipLoop runs it; the time is the
// import's plus the loop's (goal: 20 min on 2 cores), the answer is given as a fraction of the validation split's
// zero field (RMS of the measured displacements of the imaged frames; goal <= 0.30).
void BM_TactipNewSensorLoop(benchmark::State& state) {
  const std::string root = sb::resolve_data_root();
  const fs::path dir = fs::temp_directory_path() / "shearbench_bench_tactip_new_sensor";
  const sbtest::TactipVariant v = sbtest::held_out_like_variant(1000);
  sbtest::write_tactip_variant(fs::path(root) / "raw" / "tactip_shear", dir / "raw", v);
  for (auto _ : state) {
    sb::import_tactip_shear((dir / "raw").string(), (dir / "out").string());
    const sb::Dataset ds = sb::read_dataset((dir / "out").string());
    const sb::FitData cal = sb::load_calibration_data(ds, root);
    const auto indenters = sb::dataset_indenters(ds, root, "validation");
    sb::ResidualInputs in;
    in.dataset = ds.name;
    in.model_id = "hydroshear";
    in.sensor = cal.sensor;
    in.calibration = cal.samples;
    double sum = 0;
    long long n = 0;
    for (const auto& info : ds.samples)
      if (info.split == "validation") {
        in.validation.push_back(sb::to_fit_sample(info, sb::read_sample(ds, info.id), indenters.at(info.indenter)));
        const auto& m = in.validation.back().meas_px;
        for (std::size_t k = 1; k < m.size(); ++k)
          for (const sb::Vec2& d : m[k])
            if (d.allFinite()) {
              sum += d.squaredNorm();
              ++n;
            }
      }
    in.base_params = sb::load_param_set("tactip_shear").params("hydroshear");
    sb::ResidualOptions o;
    o.max_iterations = 10;
    o.selection.max_effects = 3;
    const sb::ResidualReport r = sb::run_residual_loop(in, o);
    const double zero = std::sqrt(sum / double(std::max(1LL, n)));
    state.SetLabel(r.after_model);
    state.counters["validation_rmse_px"] = r.after.validation.overall.result().rmse_px;
    state.counters["zero_field_px"] = zero;
    state.counters["of_zero_field"] = r.after.validation.overall.result().rmse_px / zero;
  }
  fs::remove_all(dir);
}
BENCHMARK(BM_TactipNewSensorLoop)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

}  // namespace
