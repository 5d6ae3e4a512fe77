// `shearbench synthesize --dataset DIR --model M [--params P.json] --samples N --out DIR`: a larger dataset made from
// a measured one (core/loop/synthetic_set.hpp): every sample copied with its path jittered, its field M's at the
// jittered path plus the source's own residual against M plus tracker noise. The loop and `evaluate` at the size
// real collections come in (docs/performance.md); the answer of a loop on it is the source's.
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "app/command.hpp"
#include "core/base/data_root.hpp"
#include "core/calibration/evaluate.hpp"
#include "core/calibration/fit_data.hpp"
#include "core/calibration/param_sets.hpp"
#include "core/data/json_read.hpp"
#include "core/data/tsd.hpp"
#include "core/effects/model_spec.hpp"
#include "core/loop/synthetic_set.hpp"

namespace fs = std::filesystem;

namespace sb::app {
namespace {

struct SynthesizeArgs {
  std::string dataset;
  std::string model;
  std::string params;
  std::string param_set;
  SyntheticSetOptions set;
  double shift_mm = 0.2;
  double turn_deg = 0.57;
  bool model_only = false;
  std::string out;
};

SampleData synthetic_sample_data(const FitSample& s) {
  SampleData d;
  for (std::size_t k = 0; k < s.X_EI.size(); ++k) d.push_pose(static_cast<double>(k) * s.dt_s, s.X_EI[k]);
  d.markers_px = s.meas_px;
  return d;
}

void check_args(const SynthesizeArgs& a) {
  require_model(a.model);
  if (!(a.shift_mm >= 0) || !std::isfinite(a.shift_mm)) throw InputError("--shift-mm", "must be a finite number >= 0");
  if (!(a.turn_deg >= 0) || !std::isfinite(a.turn_deg)) throw InputError("--turn-deg", "must be a finite number >= 0");
  if (!(a.set.noise_px >= 0) || !std::isfinite(a.set.noise_px))
    throw InputError("--noise-px", "must be a finite number >= 0");
}

int run_synthesize(const SynthesizeArgs& args, const GlobalOptions& g) {
  check_args(args);
  const std::string root = resolve_data_root(g.data_root_flag);
  Dataset ds = read_dataset(resolve_path(args.dataset, root, ""));
  const fs::path out = fs::absolute(args.out);
  if (fs::exists(out))
    throw InputError(args.out, "already exists: synthesize writes a new folder and never overwrites");
  if (args.set.samples < ds.samples.size())
    throw InputError("--samples", std::to_string(args.set.samples) + " is fewer than the source's " +
                                      std::to_string(ds.samples.size()) + " samples");
  const NamedParamSet set = load_param_set(param_set_or_default(args.param_set, ds.sensor_model));
  ParamSet params = set.params(args.model);
  if (!args.params.empty())
    params.update_from_json(params_for_model(jsonin::load_file(args.params), args.model, true, args.params),
                            args.params);
  const auto sensor = dataset_sensor(ds);
  std::vector<FitSample> source;
  std::vector<TsdSampleInfo> infos;
  for (const std::string split : {"calibration", "validation"}) {
    const auto indenters = dataset_indenters(ds, root, split);
    for (const auto& info : ds.samples)
      if (info.split == split) {
        source.push_back(to_fit_sample(info, read_sample(ds, info.id), indenters.at(info.indenter)));
        infos.push_back(info);
      }
  }
  SyntheticSetOptions o = args.set;
  o.shift_m = args.shift_mm * 1e-3;
  o.turn_rad = args.turn_deg * M_PI / 180.0;
  o.keep_residual = !args.model_only;
  const std::vector<FitSample> made = synthetic_samples(source, spec_model_factory(args.model, sensor), params, o);
  std::vector<SampleData> data;
  std::vector<TsdSampleInfo> made_infos;
  for (std::size_t k = 0; k < made.size(); ++k) {
    TsdSampleInfo info = infos[k % infos.size()];
    info.id = made[k].id;
    info.has_forces = info.has_frames = false;
    made_infos.push_back(info);
    data.push_back(synthetic_sample_data(made[k]));
  }
  ds.samples = std::move(made_infos);
  for (auto& [name, indenter] : ds.indenters) indenter.mesh = fs::absolute(ds.mesh_path(name)).string();
  ds.provenance += " | shearbench synthesize: " + std::to_string(made.size()) + " samples from " +
                   std::to_string(source.size()) + ", " + args.model + " field" +
                   (o.keep_residual ? " + the source's residual" : "") + " + " + std::to_string(o.noise_px) +
                   " px noise, paths jittered " + std::to_string(args.shift_mm) + " mm / " +
                   std::to_string(args.turn_deg) + " deg (seed " + std::to_string(o.seed) + ")";
  ds.name += "x" + std::to_string(made.size());
  write_dataset(out.string(), ds, data);
  if (!g.quiet)
    std::printf("synthesize: %zu samples from %zu of %s -> %s\n", made.size(), source.size(), args.dataset.c_str(),
                args.out.c_str());
  return 0;
}

void add_flags(CLI::App& sub, SynthesizeArgs& a) {
  add_dataset_flag(sub, a.dataset);
  sub.add_option("--model", a.model, "the model whose field the copies carry (a form with effects allowed)")->required();
  add_params_flag(sub, a.params, "its parameters (e.g. a residual report's _params.json)");
  add_param_set_flag(sub, a.param_set);
  sub.add_option("--samples", a.set.samples, "samples in the new set (at least the source's)")->capture_default_str();
  sub.add_option("--shift-mm", a.shift_mm, "standard deviation of each copy's path shift per axis")
      ->capture_default_str();
  sub.add_option("--turn-deg", a.turn_deg, "standard deviation of its turn per axis")->capture_default_str();
  sub.add_option("--noise-px", a.set.noise_px, "tracker noise per component")->capture_default_str();
  sub.add_flag("--model-only", a.model_only, "the model's field alone, without the source's residual");
  sub.add_option("--seed", a.set.seed, "seed of the jitter and the noise")->capture_default_str();
  sub.add_option("--out", a.out, "new dataset folder (refused when it exists)")->required();
}

const Subcommand<SynthesizeArgs> kSynthesizeCommand{
    "synthesize", "a larger dataset from a measured one: jittered paths, a model's field, the source's residual", 42,
    add_flags, run_synthesize};

}  // namespace
}  // namespace sb::app
