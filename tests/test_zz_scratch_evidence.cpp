// SCRATCH (not committed): the answer's evidence recomputed from a residual.json and its dataset.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include "core/base/data_root.hpp"
#include "core/calibration/fit_data.hpp"
#include "core/effects/model_spec.hpp"
#include "core/loop/effect_evidence.hpp"
namespace test_zz_scratch {
TEST_CASE("scratch evidence", "[.scratch]") {
  const std::string dir = std::getenv("EV_DATA"), jpath = std::getenv("EV_JSON");
  const auto j = nlohmann::json::parse(std::ifstream(jpath));
  const sb::Dataset ds = sb::read_dataset(dir);
  auto sensor = sb::dataset_sensor(ds);
  const std::string root = sb::resolve_data_root("");
  const auto ind = sb::dataset_indenters(ds, root);
  std::vector<sb::FitSample> cal, val;
  for (const auto& info : ds.samples)
    (info.split == "calibration" ? cal : val).push_back(sb::to_fit_sample(info, sb::read_sample(ds, info.id), ind.at(info.indenter)));
  const std::string model = j["after_model"];
  const auto spec = sb::parse_model_spec(model);
  sb::ParamSet p = sb::model_spec_params(model);
  p.update_from_json(j["after"]["params"], "x");
  std::vector<std::string> sel = spec.effects;
  if (const char* only = std::getenv("EV_ONLY")) sel = {only};
  const auto ev = sb::answer_evidence(sensor, spec.form, spec.effects, p, cal, val);
  for (const auto& e : ev) std::cout << "ANSWER " << e.effect << ": " << e.verdict << "\n\n";
  if (std::getenv("EV_ALL"))
    for (const auto& id : sb::evidenced_effects()) {
      if (std::find(spec.effects.begin(), spec.effects.end(), id) != spec.effects.end()) continue;
      const auto e = sb::answer_evidence(sensor, model, {id}, p, cal, val);
      std::cout << "OTHER " << id << ": " << e[0].verdict << "\n\n";
    }
}
}
