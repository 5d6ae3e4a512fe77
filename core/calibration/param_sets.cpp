#include "core/calibration/param_sets.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "core/base/atomic_write.hpp"
#include "core/base/data_root.hpp"
#include "core/base/error.hpp"
#include "core/base/format.hpp"
#include "core/base/install_paths.hpp"
#include "core/data/importers.hpp"
#include "core/data/json_read.hpp"
#include "core/effects/model_spec.hpp"
#include "core/models/model.hpp"

namespace fs = std::filesystem;

namespace sb {

ParamSet NamedParamSet::params(const std::string& model_id) const {
  // A form with effects starts from the set's table of its form, then its own table if the set has one.
  ParamSet p = model_spec_params(model_id);
  const std::string form = parse_model_spec(model_id).form;
  std::vector<std::string> layers = {form};
  if (model_id != form) layers.push_back(model_id);
  for (const std::string& id : layers)
    if (const auto it = tables.find(id); it != tables.end())
      p.update_from_json(it->second, (file.empty() ? name : file) + ": /params/" + id);
  return p;
}

std::string NamedParamSet::summary() const {
  std::string s = "parameter set '" + name + "'";
  if (const auto* d = provenance.is_object() ? &provenance : nullptr) {
    if (d->contains("description")) s += ": " + (*d)["description"].get<std::string>();
    if (!sensor_model().empty()) s += "\nsensor: " + sensor_model();
    if (d->contains("command")) s += "\nmade by: " + (*d)["command"].get<std::string>();
    if (d->contains("validation")) {
      s += "\nvalidation RMSE / CS (overall) on " + d->value("dataset", std::string("its dataset")) + ":";
      for (const auto& [id, v] : (*d)["validation"].items())
        if (v.contains("overall"))
          s += "\n  " + id + ": " + format_number(v["overall"].value("rmse_px", NAN)) + " px, CS " +
               format_number(v["overall"].value("cs", NAN));
    }
  }
  return s;
}

std::string NamedParamSet::sensor_model() const {
  if (name == kPublishedParamSet && file.empty()) return "";
  return provenance.is_object() ? provenance.value("sensor_model", std::string(kDefaultSensorModel))
                                : kDefaultSensorModel;
}

std::string param_sets_dir() { return (fs::path(home_dir()) / "assets" / "params").string(); }

std::vector<std::string> param_set_names() {
  std::vector<std::string> names{kPublishedParamSet};
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(param_sets_dir(), ec))
    if (e.path().extension() == ".json" && e.path().stem() != kPublishedParamSet)
      names.push_back(e.path().stem().string());
  std::sort(names.begin() + 1, names.end());
  return names;
}

NamedParamSet published_param_set() {
  NamedParamSet s;
  s.name = kPublishedParamSet;
  s.provenance = {{"description",
                   "the authors' values as their code sets them (docs/models.md), tuned for their "
                   "cameras and units, not fitted to our data"}};
  return s;
}

std::string default_param_set_for(const std::string& sensor_model) {
  if (sensor_model == kDefaultSensorModel) return kDefaultParamSet;
  for (const std::string& name : param_set_names())
    if (name != kPublishedParamSet && load_param_set(name).sensor_model() == sensor_model) return name;
  return kDefaultParamSet;
}

std::string sensor_mismatch(const NamedParamSet& set, const std::string& sensor_model) {
  const std::string fitted_on = set.sensor_model();
  if (fitted_on.empty() || fitted_on == sensor_model) return "";
  return "parameter set '" + set.name + "' was fitted on a " + fitted_on + ", not on this " + sensor_model +
         ": its values are not calibrated for this sensor";
}

std::string param_set_or_default(const std::string& requested, const std::string& sensor_model) {
  return requested.empty() ? default_param_set_for(sensor_model) : requested;
}

NamedParamSet load_param_set(const std::string& name_or_file) {
  if (name_or_file == kPublishedParamSet) return published_param_set();
  const bool is_file = name_or_file.find('/') != std::string::npos || fs::path(name_or_file).extension() == ".json";
  const std::string file = is_file ? name_or_file : (fs::path(param_sets_dir()) / (name_or_file + ".json")).string();
  if (!fs::exists(file)) {
    std::string known;
    for (const auto& n : param_set_names()) known += (known.empty() ? "" : ", ") + n;
    throw InputError(file, "no parameter set '" + name_or_file + "' (known: " + known + ")");
  }
  const nlohmann::json j = jsonin::load_file(file);
  jsonin::require_object(j, file, "");
  jsonin::reject_unknown_keys(j, {"format", "name", "provenance", "params"}, file, "");
  if (jsonin::string(jsonin::member(j, "format", file, ""), file, "/format") != "shearbench-param-set/1")
    jsonin::fail(file, "/format", "expected \"shearbench-param-set/1\"");
  NamedParamSet s;
  s.file = file;
  s.name = jsonin::string(jsonin::member(j, "name", file, ""), file, "/name");
  if (const auto* p = jsonin::find(j, "provenance")) s.provenance = *p;
  const nlohmann::json& params = jsonin::member(j, "params", file, "");
  jsonin::require_object(params, file, "/params");
  for (const auto& [id, table] : params.items()) {
    const std::string ptr = jsonin::child("/params", id);
    if (std::find(model_ids().begin(), model_ids().end(), id) == model_ids().end())
      jsonin::fail(file, ptr, "unknown model '" + id + "'");
    jsonin::require_object(table, file, ptr);
    s.tables[id] = table;
    s.params(id);  // every name known and every value in range, reported here rather than at first use
  }
  return s;
}

nlohmann::ordered_json param_set_to_json(const NamedParamSet& set) {
  nlohmann::ordered_json j;
  j["format"] = "shearbench-param-set/1";
  j["name"] = set.name;
  j["provenance"] = set.provenance;
  nlohmann::ordered_json params = nlohmann::ordered_json::object();
  for (const auto& [id, table] : set.tables) params[id] = table;
  j["params"] = params;
  return j;
}

void save_param_set(const std::string& path, const NamedParamSet& set) {
  write_file_atomic(path, param_set_to_json(set).dump(2) + "\n");
}

ParamSetData param_set_data(const nlohmann::json& provenance, const std::string& data_root,
                            const std::string& work_dir) {
  const std::string where = "parameter set provenance";
  if (!provenance.is_object() || !provenance.contains("dataset") || !provenance["dataset"].is_string())
    throw InputError(where, "no \"dataset\"");
  ParamSetData d;
  d.dir = resolve_path(provenance["dataset"].get<std::string>(), data_root, "");
  if (provenance.contains("import")) {
    const std::string source = provenance["import"].get<std::string>();
    if (source != "fots" && source != "tactip_shear")
      throw InputError(where + ": /import", "unknown importer '" + source + "' (known: fots, tactip_shear)");
    const std::string out = (fs::path(work_dir) / "imported").string();
    fs::remove_all(out);
    if (source == "fots")
      import_fots(d.dir, out);
    else
      import_tactip_shear(d.dir, out);
    d.dir = out;
  }
  if (provenance.contains("calibration_samples"))
    d.calibration_ids = provenance["calibration_samples"].get<std::vector<std::string>>();
  if (provenance.contains("validation_samples"))
    d.validation_ids = provenance["validation_samples"].get<std::vector<std::string>>();
  return d;
}

Dataset read_param_set_dataset(const ParamSetData& data) {
  Dataset ds = read_dataset(fs::absolute(data.dir).string());
  if (!data.calibration_ids.empty())
    assign_calibration_split(ds, data.calibration_ids, "calibration_samples", data.validation_ids);
  return ds;
}

}  // namespace sb
