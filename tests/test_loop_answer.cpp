// The loop's answer for a parameter set: the report, among a folder of runs, on the dataset the set was fitted on
// with HydroShear as its base.
#include <catch2/catch.hpp>

#include "temp_path.hpp"

#include <filesystem>
#include <fstream>

#include "core/loop/loop_answer.hpp"

namespace test_loop_answer {

using namespace sb;
namespace fs = std::filesystem;

namespace {

// The members load_residual_summary reads, as `shearbench residual --json` writes them.
nlohmann::json report(const std::string& dataset, const std::string& model, const std::vector<std::string>& effects) {
  std::string after_model = model;
  for (const std::string& e : effects) after_model += "+" + e;
  nlohmann::json after_params = {{"mu", 2.5}};
  if (!effects.empty()) after_params["lens_distortion.k1"] = -0.1;
  return {{"dataset", dataset},
          {"model", model},
          {"after_model", after_model},
          {"answer_labelled", after_model},
          {"before", {{"validation_rmse_px", 5.5}, {"params", {{"mu", 1.0}}}}},
          {"after", {{"validation_rmse_px", 2.9}, {"effects", effects}, {"params", after_params}}},
          {"selected", effects},
          {"candidates", nlohmann::json::array()}};
}

// A folder of runs, each a folder with its residual.json (or, for `broken`, a file that is no JSON).
struct Reports {
  fs::path dir = sbtest::temp_path("sb_test_loop_answer");
  Reports() {
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  ~Reports() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  void add(const std::string& run, const nlohmann::json& j) const {
    fs::create_directories(dir / run);
    std::ofstream(dir / run / "residual.json") << j.dump(1);
  }
  void add_broken(const std::string& run) const {
    fs::create_directories(dir / run);
    std::ofstream(dir / run / "residual.json") << "{ not json";
  }
};

NamedParamSet set_fitted_on(const std::string& dataset) {
  NamedParamSet set;
  set.name = "a_sensor";
  set.provenance = {{"dataset", dataset}};
  return set;
}

}  // namespace

TEST_CASE("loop answer: the HydroShear run on the set's own dataset, not another base or dataset", "[loop_answer]") {
  const Reports r;
  r.add("a_tacsl", report("tactip_shear", "tacsl", {"lens_distortion"}));            // another base model
  r.add("b_other", report("fots_marker_calib", "hydroshear", {"lens_distortion"}));  // another dataset
  r.add("c_injected", report("tactip_shear+viscoelastic_creep", "hydroshear", {"lens_distortion"}));
  r.add("d_answer", report("tactip_shear", "hydroshear", {"lens_distortion"}));
  // The set names its dataset as a data-root path: its last component is the report's dataset name.
  const auto answer = find_loop_answer(set_fitted_on("data:raw/tactip_shear"), r.dir.string());
  REQUIRE(answer);
  CHECK(answer->summary.file == (r.dir / "d_answer" / "residual.json").string());
  CHECK(answer->summary.after_model == "hydroshear+lens_distortion");
  CHECK(answer->summary.after_params.at("lens_distortion.k1").get<double>() == -0.1);
}

TEST_CASE("loop answer: none for a run that selected nothing, a set with no dataset, a missing folder",
          "[loop_answer]") {
  const Reports r;
  r.add("plain", report("twin_frames", "hydroshear", {}));
  CHECK_FALSE(find_loop_answer(set_fitted_on("data:twin/twin_frames"), r.dir.string()));
  CHECK_FALSE(find_loop_answer(NamedParamSet{}, r.dir.string()));
  CHECK_FALSE(find_loop_answer(set_fitted_on("data:twin/twin_frames"), (r.dir / "absent").string()));
}

TEST_CASE("loop answer: a broken report is skipped and named, the others still answer", "[loop_answer]") {
  const Reports r;
  r.add_broken("a_broken");
  r.add("b_answer", report("twin_sphere35", "hydroshear", {"lens_distortion"}));
  std::string skipped;
  const auto answer = find_loop_answer(set_fitted_on("data:twin/twin_sphere35/"), r.dir.string(), &skipped);
  REQUIRE(answer);
  CHECK(answer->summary.after_model == "hydroshear+lens_distortion");
  CHECK(skipped.find("a_broken") != std::string::npos);
}

}  // namespace test_loop_answer
