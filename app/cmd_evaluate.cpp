// `shearbench evaluate --dataset DIR --model M|all [--params P.json] [--split S] [--json OUT] [--markdown OUT.md]`:
// runs models over a tsd/1 dataset's measured poses and reports RMSE and cosine similarity per motion
// type and overall (core/calibration/evaluate.hpp), as JSON and as the paper's calibration-table layout in Markdown.
#include <cstdio>
#include <iostream>

#include "app/command.hpp"
#include "core/base/data_root.hpp"
#include "core/calibration/evaluate.hpp"
#include "core/calibration/param_sets.hpp"
#include "core/data/json_read.hpp"

namespace sb::app {
namespace {

struct EvaluateArgs {
  std::string dataset;
  std::string model;
  std::string params;
  std::string param_set;  // empty: the default for the dataset's sensor
  std::string split = "all";
  std::string json_out;
  std::string markdown_out;
  std::string predictions_out;
};

int run_evaluate(const EvaluateArgs& a, const GlobalOptions& g) {
  if (a.model != "all") require_model(a.model);
  if (!a.predictions_out.empty() && a.model == "all")
    throw InputError("--predictions", "needs one --model (the fields of one model), not 'all'");
  const std::string root = resolve_data_root(g.data_root_flag);
  const Dataset ds = read_dataset(resolve_path(a.dataset, root, ""));
  split_selected(a.split, "calibration", "--split");  // rejects an unknown split before any work
  std::vector<std::string> ids;
  if (a.model == "all")
    ids = model_ids();
  else
    ids.push_back(a.model);
  const nlohmann::json params_file = a.params.empty() ? nlohmann::json() : jsonin::load_file(a.params);

  const NamedParamSet set = load_param_set(param_set_or_default(a.param_set, ds.sensor_model));
  Warnings warnings;
  if (const std::string w = sensor_mismatch(set, ds.sensor_model); !w.empty()) warnings.add(w);
  if (!g.quiet)
    std::fprintf(stderr, "evaluate: parameter set '%s'%s\n", set.name.c_str(),
                 a.params.empty() ? "" : (", then " + a.params).c_str());
  std::vector<EvaluationResult> results;
  for (const auto& id : ids) {
    // The set's table, then --params on top.
    nlohmann::json table = set.params(id).to_json();
    table.update(params_for_model(params_file, id, ids.size() == 1, a.params));
    const ModelFactory factory = dataset_model_factory(ds, id, table, root, a.params, &warnings);
    results.push_back(evaluate_dataset(ds, factory, a.split, id, &warnings, !a.predictions_out.empty()));
    if (!g.quiet) {
      const MetricsResult o = results.back().metrics.overall.result();
      std::printf("%-17s RMSE %.3f px  CS %.3f  n %lld  (%.2f s)\n", id.c_str(), o.rmse_px, o.cs, o.n,
                  results.back().seconds);
    }
  }
  const std::string title = ds.name + " (" + a.split + ")";
  if (!g.quiet) std::printf("\n%s", evaluation_to_markdown(results, title).c_str());
  if (!a.json_out.empty()) write_file_atomic(a.json_out, evaluation_to_json(results, ds, a.split).dump(2) + "\n");
  if (!a.markdown_out.empty()) write_file_atomic(a.markdown_out, evaluation_to_markdown(results, title));
  if (!a.predictions_out.empty()) write_file_atomic(a.predictions_out, scored_fields_csv(results.front()));
  if (!g.quiet)
    for (const auto& w : warnings.messages) std::fprintf(stderr, "warning: %s\n", w.c_str());
  return 0;
}

void add_flags(CLI::App& sub, EvaluateArgs& a) {
  add_dataset_flag(sub, a.dataset);
  sub.add_option(
         "--model", a.model,
         "model id, a form with effects (hydroshear-contact+viscoelastic_creep: a residual report's answer) or 'all'")
      ->required();
  add_param_set_flag(sub, a.param_set);
  add_params_flag(sub, a.params);
  sub.add_option("--split", a.split, "calibration | validation | all")
      ->check(CLI::IsMember({"calibration", "validation", "all"}));
  sub.add_option("--json", a.json_out, "write the results as JSON (the table is printed either way)");
  sub.add_option("--markdown", a.markdown_out, "write the table as Markdown");
  sub.add_option("--predictions", a.predictions_out,
                 "write every scored marker's measured and predicted displacement as CSV (one model)");
}

const Subcommand<EvaluateArgs> kEvaluateCommand{
    "evaluate", "score shear models against a tsd/1 dataset (RMSE and CS per motion type)", 35, add_flags,
    run_evaluate};

}  // namespace
}  // namespace sb::app
