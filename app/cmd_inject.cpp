// `shearbench inject --dataset DIR --effect ID [--set name=value,...] [--hold-frames N] --out DIR`: a copy of
// a dataset with a catalogued effect put into its measured fields, undeclared (core/loop/inject.hpp), to check
// that the residual loop finds what was put in. A lens bends the recorded rest grid too (recorded_rest_px). The
// copy's poses and markers are written as tsd/1; frames and forces are not copied (a hold changes the frame
// count), meshes are referenced where they are.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <random>

#include "app/command.hpp"
#include "core/base/data_root.hpp"
#include "core/base/error.hpp"
#include "core/calibration/fit_data.hpp"
#include "core/data/tsd.hpp"
#include "core/effects/effects.hpp"
#include "core/loop/inject.hpp"

namespace fs = std::filesystem;

namespace sb::app {
namespace {

struct InjectArgs {
  std::string dataset;
  std::string effect;
  std::vector<std::string> set;  // name=value, the effect's own parameter names
  int hold_frames = 0;
  double noise_px = 0.05;
  unsigned seed = 16;
  std::string out;
};

std::map<std::string, double> parse_settings(const InjectArgs& a) {
  std::unique_ptr<Effect> effect;
  try {
    effect = make_effect(a.effect);
  } catch (const std::invalid_argument& e) {
    throw InputError("--effect", e.what());
  }
  const ParamSet& table = effect->params();
  std::map<std::string, double> values;
  for (const auto& kv : a.set) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos) throw InputError("--set", "'" + kv + "' is not name=value");
    const std::string name = kv.substr(0, eq);
    if (table.index_of(name) < 0) throw InputError("--set", a.effect + " has no parameter '" + name + "'");
    std::size_t used = 0;
    try {
      values[name] = std::stod(kv.substr(eq + 1), &used);
    } catch (const std::exception&) {
    }
    if (used == 0 || used != kv.size() - eq - 1 || !std::isfinite(values[name]))
      throw InputError("--set", "'" + kv + "': the value is not a finite number");
    const ParamSpec& spec = table.specs()[static_cast<std::size_t>(table.index_of(name))];
    if (values[name] < spec.min || values[name] > spec.max)
      throw InputError("--set", "'" + kv + "': outside " + name + "'s range [" + std::to_string(spec.min) + ", " +
                                    std::to_string(spec.max) + "]");
  }
  return values;
}

// The sample as tsd/1 data again: frame k at k dt, poses as read or repeated by a hold.
SampleData to_sample_data(const FitSample& s) {
  SampleData d;
  for (std::size_t k = 0; k < s.X_EI.size(); ++k) d.push_pose(static_cast<double>(k) * s.dt_s, s.X_EI[k]);
  d.markers_px = s.meas_px;
  return d;
}

int run_inject(const InjectArgs& a, const GlobalOptions& g) {
  const std::map<std::string, double> values = parse_settings(a);
  const std::string root = resolve_data_root(g.data_root_flag);
  Dataset ds = read_dataset(resolve_path(a.dataset, root, ""));
  const fs::path out = fs::absolute(a.out);
  if (fs::exists(out / "dataset.json") || (fs::exists(out) && fs::equivalent(ds.dir, out)))
    throw InputError(a.out, "already holds a dataset: inject writes a new folder and never overwrites one");
  const auto sensor = dataset_sensor(ds);
  const auto indenters = dataset_indenters(ds, root);
  std::mt19937_64 rng(a.seed);
  std::vector<SampleData> samples;
  for (auto& info : ds.samples) {
    FitSample s = to_fit_sample(info, read_sample(ds, info.id), indenters.at(info.indenter));
    if (a.hold_frames > 0 && info.pose_known) insert_hold(*sensor, a.hold_frames, a.noise_px, &rng, &s);
    inject_effect(*sensor, a.effect, values, &s);
    samples.push_back(to_sample_data(s));
    info.has_forces = info.has_frames = false;
  }
  for (auto& [name, indenter] : ds.indenters) indenter.mesh = fs::absolute(ds.mesh_path(name)).string();
  std::string what = a.effect;
  for (const auto& [name, value] : values) what += " " + name + "=" + std::to_string(value);
  ds.provenance += " | shearbench inject: " + what +
                   (a.hold_frames ? ", hold of " + std::to_string(a.hold_frames) + " frames at peak load" : "");
  ds.markers_rest_px = recorded_rest_px(ds.camera, a.effect, values, ds.markers_rest_px);
  ds.name += "+" + a.effect;
  write_dataset(a.out, ds, samples);
  if (!g.quiet)
    std::printf("inject: %s into %zu samples of %s -> %s\n", what.c_str(), samples.size(), a.dataset.c_str(),
                a.out.c_str());
  return 0;
}

void add_flags(CLI::App& sub, InjectArgs& a) {
  add_dataset_flag(sub, a.dataset);
  sub.add_option("--effect", a.effect, "the effect to put in (an id of the effect catalogue)")->required();
  sub.add_option("--set", a.set, "its parameters, name=value (its own names: tau_s=0.3,creep_fraction=0.3)")
      ->delimiter(',');
  sub.add_option("--hold-frames", a.hold_frames,
                 "insert a hold of N frames at each sample's peak load first (creep shows there)");
  sub.add_option("--noise-px", a.noise_px, "tracking noise on the held frames, px per component");
  sub.add_option("--seed", a.seed, "seed of that noise");
  sub.add_option("--out", a.out, "new dataset folder (refused when it already holds a dataset)")->required();
}

const Subcommand<InjectArgs> kInjectCommand{
    "inject", "a copy of a dataset with a known effect put into its measurements (checks the residual loop)", 41,
    add_flags, run_inject};

}  // namespace
}  // namespace sb::app
