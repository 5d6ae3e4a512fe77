// `shearbench fit --dataset DIR --model M [--stages a,b] [--stages-only] [--px-scale] [--robust huber] --out P.json`:
// least-squares calibration of one model (or 'all') on the dataset's calibration split
// (core/calibration/fit.hpp): the model's stages, then a joint refinement of every stage's parameters (the
// best fit it can give; the paper's stage-only procedure is --stages-only, and it can end worse than the
// starting values because each stage fits its parameters with the others held). The parameter file is written once,
// atomically, when every stage is done. Ctrl-C or SIGTERM cancels: nothing is written to --out (an existing file stays
// as it was) and the exit code is 130; with --checkpoint FILE the completed stages are kept in that separate file as
// they finish.
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <filesystem>

#include "app/command.hpp"
#include "app/interrupt.hpp"
#include "core/base/data_root.hpp"
#include "core/calibration/evaluate.hpp"
#include "core/calibration/fit_data.hpp"
#include "core/data/json_read.hpp"
#include "core/effects/model_spec.hpp"

namespace sb::app {
namespace {

struct FitArgs {
  std::string dataset;
  std::string model;
  std::vector<std::string> stages;
  std::vector<std::string> hold;
  bool stages_only = false;
  bool px_scale = false;
  std::string robust = "none";
  double robust_scale_px = 1.0;
  int max_iterations = 50;
  std::string start;
  std::string out;
  std::string checkpoint;
};

int run_fit(const FitArgs& a, const GlobalOptions& g) {
  std::vector<std::string> ids;
  if (a.model == "all")
    ids = model_ids();
  else
    ids.push_back(a.model);
  for (const auto& id : ids) require_model(id);  // unknown ids fail before any work
  for (const auto& name : a.hold) {              // so does a held name no model fits
    const bool fitted = std::any_of(ids.begin(), ids.end(), [&](const std::string& id) {
      const auto params = joint_stage(id, false).params;
      return std::find(params.begin(), params.end(), name) != params.end();
    });
    if (!fitted) throw InputError("--hold", name + ": no stage of " + a.model + " fits it");
  }
  const std::string root = resolve_data_root(g.data_root_flag);
  const Dataset ds = read_dataset(std::filesystem::absolute(resolve_path(a.dataset, root, "")).string());
  FitOptions o;
  o.stages = a.stages;
  o.hold = a.hold;
  o.joint = !a.stages_only;
  o.fit_px_scale = a.px_scale;
  o.robust = parse_robust_loss(a.robust);
  o.robust_scale_px = a.robust_scale_px;
  o.max_iterations = a.max_iterations;
  InterruptScope interrupt;
  o.cancel = interrupt.flag();
  o.progress = [&](const FitProgress& p) {
    if (!g.quiet) std::fprintf(stderr, "  %-12s iter %3d  loss %.6g\n", p.stage.c_str(), p.iteration, p.loss);
  };
  const nlohmann::json start_file = a.start.empty() ? nlohmann::json() : jsonin::load_file(a.start);

  Warnings warnings;
  const FitData data = load_calibration_data(ds, root, &warnings);
  if (!g.quiet) {
    std::fprintf(stderr, "fit: %zu calibration samples of %s\n", data.samples.size(), ds.name.c_str());
    std::fprintf(stderr, "fit: %s, then %s\n",
                 a.stages.empty() ? "every stage of the model's table" : "the stages given",
                 o.joint ? "a joint refinement of all their parameters (--stages-only: the paper's stages alone)"
                         : "nothing else (--stages-only: the paper's procedure; the default adds a joint refinement)");
  }
  std::vector<CalibrationResult> done;
  bool cancelled = false;
  for (const auto& id : ids) {
    ParamSet start = model_spec_params(id);
    start.update_from_json(params_for_model(start_file, id, ids.size() == 1, a.start), a.start);
    o.on_stage_done = [&](const CalibrationResult& partial) {
      auto all = done;
      all.push_back(partial);
      if (!a.checkpoint.empty()) write_file_atomic(a.checkpoint, fit_file_json(all, ds, o).dump(2) + "\n");
      const StageReport& s = partial.stages.back();
      if (!g.quiet)
        std::fprintf(stderr, "%s/%s: RMSE %.4f -> %.4f px, %d iterations, %d model runs, %.2f s%s%s\n", id.c_str(),
                     s.name.c_str(), s.rmse_before_px, s.rmse_after_px, s.iterations, s.evaluations, s.time_s,
                     s.note.empty() ? "" : " -- ", s.note.c_str());
    };
    done.push_back(fit_model(id, data.sensor, data.samples, start, o));
    if (done.back().cancelled) {
      cancelled = true;
      break;
    }
  }
  if (!g.quiet)
    for (const auto& w : warnings.messages) std::fprintf(stderr, "warning: %s\n", w.c_str());
  if (cancelled) {
    std::fprintf(stderr, "fit: cancelled; %s was not written%s\n", a.out.c_str(),
                 a.checkpoint.empty() ? "" : (" (completed stages are in " + a.checkpoint + ")").c_str());
    return kExitCancelled;
  }
  write_file_atomic(a.out, fit_file_json(done, ds, o).dump(2) + "\n");
  if (!g.quiet) std::fprintf(stderr, "fit: wrote %s\n", a.out.c_str());
  return 0;
}

void add_flags(CLI::App& sub, FitArgs& a) {
  add_dataset_flag(sub, a.dataset);
  sub.add_option(
         "--model", a.model,
         "model id, a form with effects (hydroshear-contact+viscoelastic_creep: a residual report's answer) or 'all'")
      ->required();
  sub.add_option("--stages", a.stages, "stages to run (default: the model's whole table); 'joint' too")->delimiter(',');
  sub.add_flag("--stages-only", a.stages_only,
               "the paper's procedure: the stages alone, without the joint refinement that follows them by default");
  sub.add_option("--hold", a.hold,
                 "parameters fitted only in the first stage that lists them, then kept (e.g. lambda_d,kappa_d: "
                 "the dilation kernel as the presses fit it)")
      ->delimiter(',');
  sub.add_flag("--px-scale", a.px_scale, "the joint refinement also fits the image scale (px/m)");
  sub.add_option("--robust", a.robust, "robust loss: none | huber | cauchy")
      ->check(CLI::IsMember({"none", "huber", "cauchy"}));
  sub.add_option("--robust-scale", a.robust_scale_px, "where the robust loss bends (px)");
  sub.add_option("--max-iterations", a.max_iterations,
                 "Levenberg-Marquardt steps taken per stage (a failed trial step does not count)");
  sub.add_option("--start", a.start, "start parameters (JSON keyed by model id, or flat for one model)");
  sub.add_option("--out", a.out, "parameter file to write (atomically, when the fit is done)")->required();
  sub.add_option("--checkpoint", a.checkpoint, "also write the completed stages here after every stage");
}

const Subcommand<FitArgs> kFitCommand{
    "fit", "calibrate a shear model on a dataset's calibration split (staged least squares)", 36, add_flags, run_fit};

}  // namespace
}  // namespace sb::app
