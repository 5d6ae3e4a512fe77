#pragma once
// Named parameter sets (assets/params/<name>.json): every model's parameters and where they came from
// (dataset, split, the command, validation RMSE and CS per motion). The workbench, `simulate`, `render`
// and `evaluate` start from kDefaultParamSet unless told otherwise (--param-set NAME, --params FILE on
// top); `published` holds the authors' values (default_params). `shearbench params --rebuild` regenerates
// every fitted set from the published values, so a set never depends on an earlier version of itself.
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/base/params.hpp"
#include "core/data/tsd.hpp"

namespace sb {

inline constexpr const char* kDefaultParamSet = "twin_sphere35";
inline constexpr const char* kPublishedParamSet = "published";

struct NamedParamSet {
  std::string name;
  std::string file;                              // where it was read from (empty: built in memory)
  nlohmann::json provenance;                     // free-form: dataset, split, command, validation per model
  std::map<std::string, nlohmann::json> tables;  // model id -> {name: value} (absent: published values)

  // The model's parameters: the published values with this set's table on top.
  ParamSet params(const std::string& model_id) const;
  // One line per model a person can read (the workbench's tooltip, `params --list`).
  std::string summary() const;
  // The sensor the set was fitted on (provenance "sensor_model"; absent: the GelSight Mini; empty for
  // 'published', which is no sensor's).
  std::string sensor_model() const;
};

// The folder of the shipped sets: assets/params in shearbench's home (base/install_paths.hpp: the installed
// share/shearbench, or the source tree of a build folder's binary). Throws InputError when there is no home.
std::string param_sets_dir();
std::vector<std::string> param_set_names();
// `name_or_file`: a set's name (assets/params/<name>.json) or a path to a set file. "published" needs no
// file. Throws InputError naming the file and the JSON pointer of a bad entry.
NamedParamSet load_param_set(const std::string& name_or_file);
NamedParamSet published_param_set();

// The set a dataset or scene starts from when none is named: kDefaultParamSet for the GelSight Mini, and for
// another sensor the first shipped set (by name) whose provenance "sensor_model" is that sensor's model
// (e.g. tactip_shear for "TacTip midi"; a set fitted on one sensor is meaningless on another). Falls back to
// kDefaultParamSet when no set is fitted for that sensor.
std::string default_param_set_for(const std::string& sensor_model);
// `requested` when the user named a set, else default_param_set_for(sensor_model).
std::string param_set_or_default(const std::string& requested, const std::string& sensor_model);
// A warning when `set` was fitted on another sensor than `sensor_model` (empty when it was not).
std::string sensor_mismatch(const NamedParamSet& set, const std::string& sensor_model);
nlohmann::ordered_json param_set_to_json(const NamedParamSet& set);

// Where a fitted set's data is, as its provenance records it: "dataset" (a data: path), and for a raw
// recording "import" (the importer, "fots" or "tactip_shear", run into `work_dir` first) and
// "calibration_samples" (the samples that calibrate; the others validate).
// With "validation_samples" too, only the listed samples are kept (a fixed subset of a large set).
struct ParamSetData {
  std::string dir;                           // a tsd/1 dataset folder
  std::vector<std::string> calibration_ids;  // empty: the dataset's own splits
  std::vector<std::string> validation_ids;   // non-empty: these validate, samples in neither list are dropped
};
ParamSetData param_set_data(const nlohmann::json& provenance, const std::string& data_root,
                            const std::string& work_dir);
// That dataset read, with its splits as the set's fit used them.
Dataset read_param_set_dataset(const ParamSetData& data);
void save_param_set(const std::string& path, const NamedParamSet& set);

}  // namespace sb
