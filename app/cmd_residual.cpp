// `shearbench residual --dataset DIR --model M [--params P.json] [--effects a,b] --json OUT.json --report OUT.md`:
// fit M on the calibration split (or take --params as the fixed base), analyse the residual's structure,
// attribute it to catalogued effects and report the validation error before and after (core/loop/residual.hpp).
// PNG plots are written beside the Markdown report.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "app/command.hpp"
#include "app/interrupt.hpp"
#include "core/base/data_root.hpp"
#include "core/base/elapsed.hpp"
#include "core/calibration/evaluate.hpp"
#include "core/calibration/fit_data.hpp"
#include "core/calibration/param_sets.hpp"
#include "core/data/json_read.hpp"
#include "core/data/tactip_sensor.hpp"
#include "core/effects/effects.hpp"
#include "core/loop/residual.hpp"
#include "core/loop/residual_report.hpp"

namespace sb::app {
namespace {

struct ResidualArgs {
  std::string dataset;
  std::string model;
  std::string params;
  std::string param_set;  // empty: the default for the dataset's sensor
  std::vector<std::string> effects;
  std::vector<std::string> calibration_ids;  // overrides the dataset's splits: these calibrate, the rest validate
  std::vector<std::string> validation_ids;  // with calibration_ids: only these validate (a fixed subset of a large set)
  int max_iterations = 30;
  int resamples = 2000;
  std::size_t max_effects = SelectionOptions{}.max_effects;
  std::size_t joint_refits = ResidualOptions{}.joint_refits_per_round;
  std::size_t search_samples = ResidualOptions{}.search_samples;
  std::size_t structure_samples = ResidualOptions{}.structure_samples;
  std::size_t search_set = ResidualOptions{}.search_set;
  bool no_model_forms = false;
  std::string json_out;
  std::string report_out;
};

// The samples of `split`; with --calibration IDS the listed samples are the calibration split and every
// other sample the validation split (recordings published without splits, e.g. the FOTS pair), or with
// --validation IDS only those (a fixed subset of a large set).
std::vector<FitSample> load_split(Dataset ds, const std::string& root, const std::string& split, const ResidualArgs& a,
                                  Warnings* warnings) {
  if (!a.validation_ids.empty() && a.calibration_ids.empty())
    throw InputError("--validation", "needs --calibration (the two name a subset of the samples together)");
  if (!a.calibration_ids.empty()) assign_calibration_split(ds, a.calibration_ids, "--calibration", a.validation_ids);
  const auto indenters = dataset_indenters(ds, root, split, warnings);
  std::vector<FitSample> out;
  for (const auto& info : ds.samples)
    if (info.split == split)
      out.push_back(to_fit_sample(info, read_sample(ds, info.id, warnings), indenters.at(info.indenter)));
  if (out.empty())
    throw InputError(ds.json_path(), "no samples in the " + split + " split (--calibration ID,... assigns them)");
  return out;
}

// A TacTip import's sensor description (sensor.tactip.description), or nullptr.
const nlohmann::json* tactip_description(const Dataset& ds) {
  const auto it = ds.sensor_extra.find("tactip");
  if (it == ds.sensor_extra.end() || !it->contains("description")) return nullptr;
  return &it->at("description");
}

// The report's last section: which sensor values the import identified from the data, which it defaulted and
// which were given, so that an answer on a new sensor says what it rests on.
std::string sensor_markdown(const Dataset& ds) {
  const nlohmann::json* d = tactip_description(ds);
  if (!d) return "";
  std::string md =
      "## The sensor\n\nThe import's sensor description (sensor.tactip.description of the dataset; "
      "docs/sensors.md): identified from the data, defaulted where the data cannot tell, or given.\n\n";
  for (const auto& line : tactip_sensor_lines(*d)) md += "- " + line + "\n";
  return md + "\n";
}

int run_residual(const ResidualArgs& a, const GlobalOptions& g) {
  const std::string root = resolve_data_root(g.data_root_flag);
  const Dataset ds = read_dataset(std::filesystem::absolute(resolve_path(a.dataset, root, "")).string());
  ResidualInputs in;
  in.dataset = ds.name;
  in.model_id = a.model;
  default_params(a.model);  // unknown ids fail before any work
  // The base fit starts from the set's values (the default set unless told otherwise); with --params the
  // base is not fitted at all.
  const NamedParamSet set = load_param_set(param_set_or_default(a.param_set, ds.sensor_model));
  in.base_params = set.params(a.model);
  ResidualOptions o;
  o.max_iterations = a.max_iterations;
  o.selection.bootstrap_resamples = a.resamples;
  o.selection.max_effects = a.max_effects;
  o.joint_refits_per_round = a.joint_refits;
  o.search_samples = a.search_samples;
  o.structure_samples = a.structure_samples;
  o.search_set = a.search_set;
  o.candidates = a.effects;
  o.model_forms = !a.no_model_forms;
  if (!a.params.empty()) {
    in.base_params.update_from_json(params_for_model(jsonin::load_file(a.params), a.model, true, a.params), a.params);
    o.fit_base = false;
  }
  for (const auto& id : o.candidates)
    if (std::find(effect_ids().begin(), effect_ids().end(), id) == effect_ids().end())
      throw InputError("--effects", "unknown effect '" + id + "'");
  Warnings warnings;
  if (const std::string w = sensor_mismatch(set, ds.sensor_model); !w.empty()) warnings.add(w);
  in.sensor = dataset_sensor(ds);
  in.calibration = load_split(ds, root, "calibration", a, &warnings);
  in.validation = load_split(ds, root, "validation", a, &warnings);
  if (!g.quiet)
    std::fprintf(stderr, "residual: %s on %s, %zu calibration + %zu validation samples, from parameter set '%s'\n",
                 a.model.c_str(), ds.name.c_str(), in.calibration.size(), in.validation.size(), set.name.c_str());
  InterruptScope interrupt;  // Ctrl-C: sb::Cancelled, exit 130, nothing written
  o.progress.cancel = interrupt.flag();
  if (!g.quiet)
    o.progress.report = [t0 = std::chrono::steady_clock::now()](const std::string& stage, double fraction) {
      // The elapsed time on every line: where a long run spends it reads off the log.
      std::fprintf(stderr, "residual: [%3.0f%%] %6.0f s  %s\n", 100.0 * std::max(0.0, fraction), seconds_since(t0),
                   stage.c_str());
    };
  const ResidualReport rep = run_residual_loop(in, o);

  const std::filesystem::path report = std::filesystem::absolute(a.report_out);
  const std::string stem = report.stem().string();
  const auto plots = write_residual_plots(rep, report.parent_path().string(), stem);
  // The loop's answer as a parameter file: `--model <after_model> --params <it>` in evaluate, simulate, fit.
  const std::filesystem::path params_out = report.parent_path() / (stem + "_params.json");
  write_file_atomic(params_out.string(), final_model_params_json(rep).dump(2) + "\n");
  write_file_atomic(report.string(), residual_to_markdown(rep, plots) + sensor_markdown(ds));
  nlohmann::json rj = residual_to_json(rep);
  if (const nlohmann::json* d = tactip_description(ds)) rj["sensor_description"] = *d;
  write_file_atomic(a.json_out, rj.dump(2) + "\n");
  if (!g.quiet) {
    for (const auto& w : warnings.messages) std::fprintf(stderr, "warning: %s\n", w.c_str());
    const MetricsResult b = rep.before.validation.overall.result(), f = rep.after.validation.overall.result();
    if (!rep.model_form.selected.empty())
      std::fprintf(stderr, "residual: model form selected: %s (validation RMSE %.4f px%s)\n",
                   rep.model_form.selected.c_str(),
                   validation_rmse(rep.model_form.fits.at(rep.model_form.selected).fit.validation),
                   rep.model_form.held.empty() ? "" : "; fitted with the dilation kernel held at the presses' fit");
    std::fprintf(stderr, "residual: effects on %s: [%s]\n", rep.effects.form.c_str(),
                 effect_set_key(rep.effects.selection.selected).c_str());
    std::fprintf(stderr, "residual: answer %s; validation RMSE %.4f -> %.4f px (%.1f s); wrote %s, %s, %s\n",
                 rep.after_model.c_str(), b.rmse_px, f.rmse_px, rep.time_s, a.json_out.c_str(), report.string().c_str(),
                 params_out.string().c_str());
  }
  return 0;
}

void add_flags(CLI::App& sub, ResidualArgs& a) {
  add_dataset_flag(sub, a.dataset);
  sub.add_option("--model", a.model, "base model id")->required();
  add_params_flag(sub, a.params, "fixed base parameters (default: fit them)");
  add_param_set_flag(sub, a.param_set);
  sub.add_option("--effects", a.effects, "candidate effects (default: the whole catalogue)")->delimiter(',');
  sub.add_option("--calibration", a.calibration_ids,
                 "sample ids that calibrate (the others validate), instead of the dataset's splits")
      ->delimiter(',');
  sub.add_option(
         "--validation", a.validation_ids,
         "with --calibration: only these sample ids validate, the rest are left out (a fixed subset of a large set)")
      ->delimiter(',');
  sub.add_option("--max-iterations", a.max_iterations,
                 "Levenberg-Marquardt steps taken per stage (a failed trial step does not count)");
  sub.add_option("--resamples", a.resamples, "bootstrap resamples");
  sub.add_option("--max-effects", a.max_effects, "greedy rounds: at most this many effects are selected")
      ->check(CLI::Range(1, 10));
  sub.add_option("--joint-refits", a.joint_refits,
                 "per round, the candidates (best alone first) refitted jointly with the form; the rest are screened")
      ->check(CLI::Range(1, 100));
  sub.add_option("--search-samples", a.search_samples,
                 "calibration samples (evenly spaced) the fits that rerun the form see during the search; 0: all. "
                 "Scores use every sample, and the answer is refitted on all")
      ->check(CLI::Range(0, 1000000));
  sub.add_option("--search-set", a.search_set,
                 "samples of both splits (evenly spaced) the search sees: its fits, scores, fingerprints and "
                 "bootstraps; 0: all. The base and the answer are then refitted on every calibration sample and "
                 "scored on every sample")
      ->check(CLI::Range(0, 100000000))
      ->capture_default_str();
  sub.add_option("--structure-samples", a.structure_samples,
                 "samples of both splits (evenly spaced) the residual structure describes; 0: all. The errors before "
                 "and after use every sample")
      ->check(CLI::Range(0, 1000000))
      ->capture_default_str();
  sub.add_flag(
      "--no-model-forms", a.no_model_forms,
      "skip the model-form round (hydroshear: its layer, stick, layer+stick and contact variants fitted and scored "
      "against it; docs/effects.md)");
  sub.add_option("--json", a.json_out, "JSON result (written atomically)")->required();
  sub.add_option("--report", a.report_out, "Markdown report; PNG plots are written beside it")->required();
}

const Subcommand<ResidualArgs> kResidualCommand{
    "residual", "attribute a model's residual to catalogued effects (fit, analyse, select, report)", 39, add_flags,
    run_residual};

}  // namespace
}  // namespace sb::app
