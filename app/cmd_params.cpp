// `shearbench params`: the shipped parameter sets (assets/params/<name>.json) with their provenance, and
// `--rebuild`, which regenerates every fitted set: each model fitted on the set's dataset's calibration
// split from the published values (stages, then the joint refinement: `fit` with no flags) and scored on
// its validation split. `shearbench --reproducible params --rebuild` writes the same bytes every time.
#include <unistd.h>
#include <cstdio>
#include <filesystem>

#include "app/command.hpp"
#include "core/base/atomic_write.hpp"
#include "core/base/data_root.hpp"
#include "core/base/error.hpp"
#include "core/calibration/param_sets.hpp"
#include "core/calibration/report.hpp"
#include "core/data/tsd.hpp"

namespace sb::app {
namespace {

// A fitted set: its name, the dataset it is fitted on and what it is for. A raw recording names its
// importer; one published without splits names the samples that calibrate (the others validate). A large
// set is fitted on its first `calibration_first` calibration samples (0: all) and scored on every
// `validation_every`-th validation sample (the lists go into the provenance, so the reproduction test
// scores the same samples).
struct SetRecipe {
  const char* name;
  const char* dataset;
  const char* description;
  const char* import = nullptr;
  std::vector<std::string> calibration_samples = {};
  int calibration_first = 0;  // 0: the dataset's calibration split
  int validation_every = 1;
  int max_iterations = 50;  // per stage (FitOptions)
};

const std::vector<SetRecipe>& recipes() {
  static const std::vector<SetRecipe> r = {
      {"twin_sphere35", "data:twin/twin_sphere35",
       "the default: fitted on the FE twin of the HydroShear paper's calibration (35 mm sphere on a GelSight Mini)"},
      {"twin_sphere8", "data:twin/twin_sphere8", "fitted on the FE twin with an 8 mm sphere (smaller contacts)"},
      {"real_fots_pair",
       "data:raw/fots_marker_calib",
       "fitted on a real GelSight press (FOTS's marker calibration pair; sphere pose estimated from the image at "
       "import, so depth and travel are uncertain: docs/tracking.md), scored on the real shear frame",
       "fots",
       {"press"}},
      // The whole calibration split (1000 samples), scored on every 5th validation sample, at most 10 steps per
      // stage (every model's fit on it within minutes: docs/performance.md).
      {"tactip_shear",
       "data:raw/tactip_shear",
       "fitted on the real TacTip set (its own sensor: dome, pins 3 mm below the skin, fitted pinhole camera); "
       "a flat surface pressed, tilted, slid and twisted with known inputs",
       "tactip_shear",
       {},
       0,
       5,
       10},
  };
  return r;
}

nlohmann::json recipe_provenance(const SetRecipe& recipe) {
  nlohmann::json p = {{"description", recipe.description}, {"dataset", recipe.dataset}};
  if (recipe.import != nullptr) p["import"] = recipe.import;
  if (!recipe.calibration_samples.empty()) p["calibration_samples"] = recipe.calibration_samples;
  return p;
}

// The recipe's subset of a large set, in the dataset's order, written into the provenance.
void choose_samples(const SetRecipe& recipe, ParamSetData& data, nlohmann::json& provenance) {
  const Dataset ds = read_dataset(std::filesystem::absolute(data.dir).string());
  int n_val = 0;
  for (const auto& s : ds.samples) {
    const bool wanted = recipe.calibration_first == 0 ||
                        static_cast<int>(data.calibration_ids.size()) < recipe.calibration_first;
    if (s.split == "calibration" && wanted)
      data.calibration_ids.push_back(s.id);
    else if (s.split == "validation" && n_val++ % recipe.validation_every == 0)
      data.validation_ids.push_back(s.id);
  }
  provenance["calibration_samples"] = data.calibration_ids;
  provenance["validation_samples"] = data.validation_ids;
}

struct ParamsArgs {
  bool rebuild = false;
  std::vector<std::string> sets;  // empty: all
  std::string out_dir;            // empty: assets/params
};

nlohmann::json validation_json(const EvaluationResult& e, const Dataset& ds) {
  nlohmann::json m = evaluation_to_json({e}, ds, "validation")["models"][e.model_id];
  m.erase("samples");
  m.erase("seconds");
  return m;
}

NamedParamSet fit_set(const SetRecipe& recipe, const std::string& root, const GlobalOptions& g) {
  const std::filesystem::path work = std::filesystem::temp_directory_path() /
                                     ("shearbench_params_" + std::to_string(::getpid()));
  struct RemoveWork {
    std::filesystem::path dir;
    ~RemoveWork() {
      std::error_code ec;
      std::filesystem::remove_all(dir, ec);
    }
  } remove_work{work};
  nlohmann::json provenance = recipe_provenance(recipe);
  ParamSetData data = param_set_data(provenance, root, work.string());
  const bool subset = recipe.calibration_first > 0 || recipe.validation_every > 1;
  if (subset) choose_samples(recipe, data, provenance);
  FidelityOptions o;
  o.dataset_dirs = {data.dir};
  o.calibration_ids = data.calibration_ids;
  o.validation_ids = data.validation_ids;
  o.fit.joint = true;  // the best fit `fit` gives with no flags
  o.fit.max_iterations = recipe.max_iterations;
  o.data_root = root;
  if (!g.quiet) o.log = [](const std::string& line) { std::fprintf(stderr, "params: %s\n", line.c_str()); };
  const DatasetFidelity r = run_fidelity(o).at(0);
  const Dataset ds = read_param_set_dataset(data);
  NamedParamSet set;
  set.name = recipe.name;
  nlohmann::json validation = nlohmann::json::object(), published = nlohmann::json::object();
  for (std::size_t i = 0; i < r.fits.size(); ++i) {
    const std::string& id = r.fits[i].model_id;
    set.tables[id] = r.fits[i].params.to_json();
    validation[id] = validation_json(r.fitted[i], ds);
    published[id] = validation_json(r.defaults[i], ds);
  }
  if (ds.sensor_model != kDefaultSensorModel) provenance["sensor_model"] = ds.sensor_model;
  const std::string fitted_on = recipe.calibration_first > 0
                                    ? "the first " + std::to_string(recipe.calibration_first) + " samples of"
                                    : "every sample of";
  provenance["split"] = subset ? "fitted on " + fitted_on + " the calibration split, scored on every " +
                                     std::to_string(recipe.validation_every) + "th sample of the validation split"
                        : recipe.calibration_samples.empty()
                            ? "fitted on the calibration split, scored on the validation split"
                            : "fitted on the calibration samples, scored on the others";
  provenance["fit"] =
      std::string("every model from the published values: its stages, then the joint refinement") +
      (recipe.max_iterations != 50 ? ", at most " + std::to_string(recipe.max_iterations) + " iterations per stage"
                                   : "") +
      (recipe.calibration_samples.empty() ? "" : " (a stage with no calibration sample of its motion keeps them)");
  provenance["command"] = std::string("shearbench --reproducible params --rebuild --set ") + recipe.name;
  provenance["validation"] = validation;
  provenance["validation_published"] = published;
  set.provenance = provenance;
  return set;
}

int run_params(const ParamsArgs& a, const GlobalOptions& g) {
  if (!a.rebuild) {
    for (const auto& name : param_set_names()) {
      const NamedParamSet s = load_param_set(name);
      std::printf("%s%s\n%s\n\n", name.c_str(), name == kDefaultParamSet ? " (default)" : "", s.summary().c_str());
    }
    return 0;
  }
  const std::string root = resolve_data_root(g.data_root_flag);
  const std::string dir = a.out_dir.empty() ? param_sets_dir() : a.out_dir;
  std::filesystem::create_directories(dir);
  bool any = false;
  for (const SetRecipe& recipe : recipes()) {
    if (!a.sets.empty() && std::find(a.sets.begin(), a.sets.end(), recipe.name) == a.sets.end()) continue;
    any = true;
    const std::string path = (std::filesystem::path(dir) / (std::string(recipe.name) + ".json")).string();
    save_param_set(path, fit_set(recipe, root, g));
    if (!g.quiet) std::fprintf(stderr, "params: wrote %s\n", path.c_str());
  }
  if (!any)
    throw InputError("--set",
                     "no fitted set of that name (twin_sphere35, twin_sphere8, real_fots_pair, tactip_shear; "
                     "'published' is not fitted)");
  return 0;
}

void add_flags(CLI::App& sub, ParamsArgs& a) {
  sub.add_flag("--rebuild", a.rebuild, "refit the fitted sets from the published values and write them");
  sub.add_option("--set", a.sets, "only these sets (with --rebuild)")->delimiter(',');
  sub.add_option("--out-dir", a.out_dir,
                 "where --rebuild writes (default: assets/params in shearbench's home, see --home)");
}

const Subcommand<ParamsArgs> kParamsCommand{
    "params", "the shipped parameter sets and their provenance; --rebuild refits them", 38, add_flags, run_params};

}  // namespace
}  // namespace sb::app
