// The workbench's view of a residual analysis: reading the JSON, the corrected model, residual fields
// and the worker that computes the corrected model's fields along a replay.
#include <catch2/catch.hpp>

#include "temp_path.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>

#include "core/base/error.hpp"
#include "core/loop/residual_view.hpp"
#include "model_fixtures.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_residual_view {

using namespace sb;

namespace {

constexpr double kExact = 1e-12;
const double kNaN = std::numeric_limits<double>::quiet_NaN();

// A residual JSON as `shearbench residual` writes it (the members the workbench reads), with
// candidates deliberately out of rank order.
nlohmann::json residual_json() {
  return nlohmann::json::parse(R"({
    "dataset": "twin/twin_sphere8", "model": "fots-reimpl",
    "before": {"validation_rmse_px": 0.40, "params": {"kappa_s": 15000.0}},
    "candidates": [
      {"effect": "tracker_bias", "validation_rmse_px": 0.39, "improvement_pct": 2.5, "ci95_pct": [-1.0, 6.0],
       "accepted": false, "reason": "interval includes zero"},
      {"effect": "camera_misalignment", "validation_rmse_px": 0.20, "improvement_pct": 50.0,
       "ci95_pct": [44.0, 55.0], "accepted": true, "reason": "selected"},
      {"effect": "lens_distortion", "validation_rmse_px": null, "improvement_pct": null, "ci95_pct": [null, null]}
    ],
    "selected": ["camera_misalignment"],
    "after": {"effects": ["camera_misalignment"], "validation_rmse_px": 0.20,
              "params": {"camera_misalignment.scale": 1.2, "camera_misalignment.rotation_rad": 0.0}}
  })");
}

std::string write_temp(const std::string& name, const nlohmann::json& j) {
  const auto path = sbtest::temp_path("sb_test_residual_view_" + name).string() + ".json";
  std::ofstream(path) << j.dump(1);
  return path;
}

// The message of the InputError that loading `j` throws ("" when it loads).
std::string load_error(const nlohmann::json& j) {
  try {
    load_residual_summary(write_temp("bad", j));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("residual summary: metrics, selection, candidates ranked by improvement", "[residual_view]") {
  const ResidualSummary s = load_residual_summary(write_temp("good", residual_json()));
  CHECK(s.model_id == "fots-reimpl");
  CHECK(s.dataset == "twin/twin_sphere8");
  CHECK(s.before_rmse_px == 0.40);
  CHECK(s.after_rmse_px == 0.20);
  const ParamSet base = fitted_base_params(s);
  CHECK(base.get("kappa_s") == 15000.0);
  CHECK(base.size() == default_params("fots-reimpl").size());  // the base table, no effect parameters
  REQUIRE(s.selected == std::vector<std::string>{"camera_misalignment"});
  REQUIRE(s.candidates.size() == 3);
  CHECK(s.candidates[0].effect == "camera_misalignment");
  CHECK(s.candidates[0].ci95_low_pct == 44.0);
  CHECK(s.candidates[0].accepted);
  CHECK(s.candidates[1].effect == "tracker_bias");
  CHECK(s.candidates[1].reason == "interval includes zero");
  CHECK(s.candidates[2].effect == "lens_distortion");  // unscored: last
  CHECK(std::isnan(s.candidates[2].improvement_pct));
}

TEST_CASE("residual summary: each candidate's reason in two words for the table", "[residual_view]") {
  // One candidate per rule of the selection (core/loop/residual_select.cpp), as residual_to_json writes them;
  // where two apply, the one its reason names first: a fingerprint not found before a veto (the screened
  // gravity_preload below has no fingerprint; a bound with a fingerprint not found is "no evidence").
  nlohmann::json j = residual_json();
  j["model_form_symptoms"] = nlohmann::json::array();  // a report that records the rules
  auto cand = [](const char* effect, double gain, nlohmann::json extra) {
    nlohmann::json c = {{"effect", effect},        {"validation_rmse_px", 0.3},
                        {"improvement_pct", gain}, {"ci95_pct", {gain - 1, gain + 1}},
                        {"accepted", false},       {"reason", "..."}};
    if (extra.is_object()) c.update(extra);  // {} is null, not an empty object
    return c;
  };
  j["candidates"] = {
      cand("camera_misalignment", 50, {{"accepted", true}}),
      cand("load_stiffening", 30,
           {{"model_form_symptom", true}, {"veto", "load_stiffening.beta_per_m = 2000 at a bound"}}),
      cand("gravity_preload", 0.2, {{"veto", "screened: alone over the fitted base it gains 0.20% (< 0.50%)"}}),
      cand("viscoelastic_creep", 12,
           {{"model_form_symptom", true},
            {"veto", "creep_fraction = 1 at a bound"},
            {"fingerprint", {{"found", false}}}}),
      cand("subsurface_markers", 13, {{"fingerprint", {{"found", false}, {"verdict", "wrong at the grid scale"}}}}),
      cand("lens_distortion", 3,
           {{"fingerprint", {{"found", true}}}, {"veto", "the whole field disagrees with the evidence"}}),
      cand("tracker_bias", 2, {}),
      {{"effect", "edge_constraint"},
       {"validation_rmse_px", nullptr},
       {"improvement_pct", nullptr},
       {"ci95_pct", {nullptr, nullptr}}}};
  const ResidualSummary s = load_residual_summary(write_temp("verdicts", j));
  std::map<std::string, std::string> verdict;
  for (const auto& c : s.candidates) verdict[c.effect] = c.verdict;
  CHECK(verdict["camera_misalignment"] == "selected");
  CHECK(verdict["load_stiffening"] == "at a bound");
  CHECK(verdict["gravity_preload"] == "screened");
  CHECK(verdict["viscoelastic_creep"] == "no evidence");
  CHECK(verdict["subsurface_markers"] == "no evidence");
  CHECK(verdict["lens_distortion"] == "vetoed");
  CHECK(verdict["tracker_bias"] == "within noise");
  CHECK(verdict["edge_constraint"] == "not scored");
  // The fixture above, as reports were before they recorded the rules: no fields to tell, no guess.
  const ResidualSummary old = load_residual_summary(write_temp("good", residual_json()));
  CHECK(old.candidates[1].verdict == "not selected");
}

TEST_CASE("residual summary: the contact-frame tables, none in older reports", "[residual_view]") {
  CHECK(load_residual_summary(write_temp("no_cf", residual_json())).contact_frame.empty());
  nlohmann::json j = residual_json();
  j["residual_before"]["covariates"] = nlohmann::json::parse(R"([
    {"covariate": "loading state", "unit": "", "bins": [{"bin": "loading", "rms_px": 1.0, "count": 3}]},
    {"covariate": "contact frame: phase", "unit": "", "bins": [
      {"bin": "loading", "rms_px": 1.5, "count": 10, "mean_radial_px": 0.25, "mean_along_travel_px": 0.0},
      {"bin": "slide", "rms_px": null, "count": 0, "mean_radial_px": null, "mean_along_travel_px": null}]}])");
  const ResidualSummary s = load_residual_summary(write_temp("cf", j));
  REQUIRE(s.contact_frame.size() == 1);  // the plain covariate table is not a contact-frame one
  const ContactFrameTableView& t = s.contact_frame[0];
  CHECK(t.name == "contact frame: phase");
  CHECK(t.bins == std::vector<std::string>{"loading", "slide"});
  CHECK(t.count == std::vector<long>{10, 0});
  CHECK(t.rms_px[0] == 1.5);
  CHECK(t.mean_radial_px[0] == 0.25);
  CHECK(t.mean_along_px[0] == 0.0);
  CHECK(std::isnan(t.rms_px[1]));
  j["residual_before"]["covariates"][1]["bins"][0]["count"] = "ten";
  CHECK_THAT(load_error(j), Catch::Contains("/residual_before/covariates/1/bins/0/count"));
}

TEST_CASE("residual summary: the input-response rows, none in older reports or without an analysis",
          "[residual_view]") {
  CHECK(load_residual_summary(write_temp("no_ir", residual_json())).input_response.empty());
  nlohmann::json j = residual_json();
  j["input_response_before"] = nullptr;  // a split without scored frames
  CHECK(load_residual_summary(write_temp("null_ir", j)).input_response.empty());
  j["input_response_before"] = nlohmann::json::parse(R"({"responses": [
      {"change": "at the reference", "measured_rms_px": 11.0, "model_rms_px": 7.5, "gain": 1.4,
       "after_gain_rms_px": 2.0},
      {"change": "travel x +2.9 mm", "measured_rms_px": 5.0, "model_rms_px": 2.25, "gain": 2.2,
       "after_gain_rms_px": 0.9}], "inputs_only_rmse_px": 2.1, "model_rmse_px": 5.6})");
  const ResidualSummary s = load_residual_summary(write_temp("ir", j));
  REQUIRE(s.input_response.size() == 2);
  CHECK(s.input_response[1].change == "travel x +2.9 mm");
  CHECK(s.input_response[1].gain == 2.2);
  CHECK(s.input_response[1].after_gain_rms_px == 0.9);
  CHECK(s.inputs_only_rmse_px == 2.1);
  j["input_response_before"]["responses"][1]["gain"] = "two";
  CHECK_THAT(load_error(j), Catch::Contains("/input_response_before/responses/1/gain"));
  j["input_response_before"]["responses"] = 3;
  CHECK_THAT(load_error(j), Catch::Contains("/input_response_before/responses"));
}

TEST_CASE("residual summary: the mean residual per bin, its RMS and whole-field shift, empty bins left out",
          "[residual_view]") {
  CHECK(load_residual_summary(write_temp("no_bins", residual_json())).binned_means.empty());
  nlohmann::json j = residual_json();
  // Two markers: means (3, 4) and (1, 0) px. RMS = sqrt((25 + 1) / 2) = sqrt(13); shift = (2, 2).
  j["residual_before"]["binned_mean_fields"] = nlohmann::json::parse(R"json([
    {"covariate": "travel direction", "bins": [
      {"bin": "none", "frames": 0, "mean_px": [[0, 0], [0, 0]]},
      {"bin": "+x (+u)", "frames": 12, "mean_px": [[3, 4], [1, 0]]}]}])json");
  const ResidualSummary s = load_residual_summary(write_temp("bins", j));
  REQUIRE(s.binned_means.size() == 1);
  const BinnedMeanView& b = s.binned_means[0];
  CHECK(b.covariate == "travel direction");
  CHECK(b.bin == "+x (+u)");
  CHECK(b.frames == 12);
  CHECK(b.rms_px == Approx(std::sqrt(13.0)).epsilon(1e-12));
  CHECK((b.shift_px - Vec2(2.0, 2.0)).norm() < 1e-12);
  j["residual_before"]["binned_mean_fields"][0]["bins"][1]["mean_px"][1] = {1};
  CHECK_THAT(load_error(j), Catch::Contains("/residual_before/binned_mean_fields/0/bins/1/mean_px/1"));
  j["residual_before"]["binned_mean_fields"] = "maps";
  CHECK_THAT(load_error(j), Catch::Contains("/residual_before/binned_mean_fields"));
}

TEST_CASE("residual summary: bad files are InputErrors naming the file and the entry", "[residual_view]") {
  CHECK_THROWS_AS(load_residual_summary("/nonexistent/residual.json"), InputError);
  auto j = residual_json();
  j["model"] = "nosuchmodel";
  CHECK_THAT(load_error(j), Catch::Contains("/model"));
  j = residual_json();
  j["selected"] = {"wobble"};
  CHECK_THAT(load_error(j), Catch::Contains("/selected/0") && Catch::Contains("unknown effect 'wobble'"));
  j = residual_json();
  j["after"]["effects"] = nlohmann::json::array();
  CHECK_THAT(load_error(j), Catch::Contains("/after/effects"));
  j = residual_json();
  j["after"]["params"]["camera_misalignment.scale"] = 7.0;  // outside [0.8, 1.25]
  CHECK_THAT(load_error(j), Catch::Contains("/after/params"));
  j = residual_json();
  j["candidates"][1]["ci95_pct"] = {1.0};
  CHECK_THAT(load_error(j), Catch::Contains("/candidates/1/ci95_pct"));
  j = residual_json();
  j["before"]["params"]["no_such_param"] = 1.0;
  CHECK_THAT(load_error(j), Catch::Contains("/before/params"));
  j = residual_json();
  j["before"].erase("validation_rmse_px");
  CHECK_THAT(load_error(j), Catch::Contains("/before") && Catch::Contains("validation_rmse_px"));
  CHECK(load_error(residual_json()).empty());
}

TEST_CASE("corrected model: base wrapped with the selected effects at the fitted parameters", "[residual_view]") {
  const auto sensor = sbtest::test_sensor();
  const auto sphere = sbtest::sphere_indenter(0.004);
  const ResidualSummary s = load_residual_summary(write_temp("good", residual_json()));
  auto corrected = make_corrected_model(s, sensor, sphere);
  auto base = make_model("fots-reimpl", sensor, sphere);
  CHECK(corrected->params().get("camera_misalignment.scale") == 1.2);
  // A press 1 mm deep off-centre, then a slide: camera_misalignment at rotation 0 and scale 1.2 maps
  // every displacement d to 1.2 d (R(0) = I), so the corrected field is exactly 1.2 x the base field.
  FieldOutput a, b;
  for (int k = 1; k <= 5; ++k) {
    const Pose X = make_pose(Vec3(1e-3 + 1e-4 * k, 0, 0.004 - 2e-4 * k), Quat::Identity());
    corrected->step(X, 0.02, &a);
    base->step(X, 0.02, &b);
  }
  REQUIRE(a.disp_px.size() == b.disp_px.size());
  double largest = 0;
  for (std::size_t i = 0; i < a.disp_px.size(); ++i) {
    CHECK((a.disp_px[i] - 1.2 * b.disp_px[i]).norm() < 1e-9);
    largest = std::max(largest, b.disp_px[i].norm());
  }
  CHECK(largest > 0.1);  // the press does move markers: the check above is not 0 == 0
}

// Issue 31: the loop's answer is the selected model form with the selected effects on it. A report that
// selected hydroshear-contact and then camera_misalignment must give exactly that model, not the base with the
// effect: the section says the same as the report.
TEST_CASE("corrected model: the selected model form with the effects selected on it", "[residual_view]") {
  const auto sensor = sbtest::test_sensor();
  const auto sphere = sbtest::sphere_indenter(0.004);
  auto j = residual_json();
  j["model"] = "hydroshear";
  j["before"]["params"] = {{"kappa_s", 15000.0}};
  j["model_form_selected"] = "hydroshear-contact";
  j["after_model"] = "hydroshear-contact+camera_misalignment";
  const ResidualSummary s = load_residual_summary(write_temp("form", j));
  CHECK(s.after_model == "hydroshear-contact+camera_misalignment");
  CHECK(s.model_form == "hydroshear-contact");
  auto corrected = make_corrected_model(s, sensor, sphere);
  CHECK(corrected->id() == "hydroshear-contact+camera_misalignment");
  // camera_misalignment at scale 1.2 and rotation 0 is exactly 1.2 x its form's field (as above).
  auto form = make_model("hydroshear-contact", sensor, sphere);
  ParamSet p = form->params();
  for (std::size_t i = 0; i < p.size(); ++i) p.set(i, corrected->params().get(p.specs()[i].name));
  form->set_params(p);
  FieldOutput a, b;
  for (int k = 1; k <= 5; ++k) {
    const Pose X = make_pose(Vec3(1e-3 + 1e-4 * k, 0, 0.004 - 2e-4 * k), Quat::Identity());
    corrected->step(X, 0.02, &a);
    form->step(X, 0.02, &b);
  }
  double largest = 0;
  for (std::size_t i = 0; i < a.disp_px.size(); ++i) {
    CHECK((a.disp_px[i] - 1.2 * b.disp_px[i]).norm() < 1e-9);
    largest = std::max(largest, b.disp_px[i].norm());
  }
  CHECK(largest > 0.1);
  // Older reports (no after_model) mean the base with the selection; an answer whose effects are not the
  // selection is refused, naming the entry.
  CHECK(load_residual_summary(write_temp("old", residual_json())).after_model == "fots-reimpl+camera_misalignment");
  j["after_model"] = "hydroshear-contact+tracker_bias";
  CHECK_THAT(load_error(j), Catch::Contains("/after_model"));
  j["after_model"] = "hydroshear-nope+camera_misalignment";
  CHECK_THAT(load_error(j), Catch::Contains("/after_model") && Catch::Contains("unknown model"));
}

TEST_CASE("residual field is measured minus predicted; a lost marker stays NaN", "[residual_view]") {
  const std::vector<Vec2> measured = {Vec2(1.0, 2.0), Vec2(kNaN, kNaN), Vec2(0.0, 0.0)};
  const std::vector<Vec2> predicted = {Vec2(0.5, 0.5), Vec2(1.0, 1.0)};
  const auto r = residual_field(measured, predicted);
  REQUIRE(r.size() == 3);
  CHECK((r[0] - Vec2(0.5, 1.5)).norm() < kExact);
  CHECK(std::isnan(r[1].x()));
  CHECK(std::isnan(r[2].x()));  // no prediction for this marker
  CHECK(residual_field({}, predicted).empty());
}

TEST_CASE("field series job: the fields of stepping the model along the path; clear cancels", "[residual_view]") {
  const auto sensor = sbtest::test_sensor();
  const auto sphere = sbtest::sphere_indenter(0.004);
  std::vector<Pose> path;
  for (int k = 1; k <= 12; ++k) path.push_back(make_pose(Vec3(0, 1e-4 * k, 0.004 - 1e-4 * k), Quat::Identity()));
  auto reference = make_model("tacsl", sensor, sphere);
  FieldSeriesJob job;
  job.start(reference->clone(), path, 0.02);
  job.wait();
  CHECK_FALSE(job.running());
  const auto& series = job.result();
  REQUIRE(series.size() == path.size());
  FieldOutput out;
  for (std::size_t k = 0; k < path.size(); ++k) {
    reference->step(path[k], 0.02, &out);
    REQUIRE(series[k].size() == out.disp_px.size());
    for (std::size_t i = 0; i < out.disp_px.size(); ++i) CHECK((series[k][i] - out.disp_px[i]).norm() < kExact);
  }
  job.clear();
  CHECK(job.result().empty());
}

}  // namespace test_residual_view

namespace test_residual_view_evidence {

using namespace sb;

// `selected` as residual_to_json writes it now: each effect with its evidence. The summary keeps the ids, the
// labels and the answer's parameters at a bound; the selected candidate's verdict says found or unshown cause.
TEST_CASE("residual summary: selected effects with their evidence", "[residual_view]") {
  auto j = nlohmann::json::parse(R"json({
    "dataset": "twin/twin_sphere8", "model": "fots-reimpl",
    "before": {"validation_rmse_px": 0.40, "params": {"kappa_s": 15000.0}},
    "candidates": [
      {"effect": "camera_misalignment", "validation_rmse_px": 0.20, "improvement_pct": 50.0,
       "ci95_pct": [44.0, 55.0], "accepted": true, "reason": "selected"}],
    "model_form_symptoms": [],
    "selected": [{"effect": "camera_misalignment", "fingerprint_found": false, "evidence": "camera roll: not found"}],
    "answer_labelled": "fots-reimpl + camera_misalignment (correction of unshown cause)",
    "answer_at_bound": [{"param": "camera_misalignment.scale", "value": 1.25, "bound": "upper", "is_default": false}],
    "after": {"effects": ["camera_misalignment"], "validation_rmse_px": 0.20,
              "params": {"camera_misalignment.scale": 1.25, "camera_misalignment.rotation_rad": 0.0}}
  })json");
  const auto path = sbtest::temp_path("sb_test_residual_view_evidence").string() + ".json";
  std::ofstream(path) << j.dump(1);
  const ResidualSummary s = load_residual_summary(path);
  REQUIRE(s.selected == std::vector<std::string>{"camera_misalignment"});
  REQUIRE(s.selected_evidence.size() == 1);
  CHECK(s.selected_evidence[0].recorded);
  CHECK_FALSE(s.selected_evidence[0].found);
  CHECK(s.selected_evidence[0].evidence == "camera roll: not found");
  CHECK(s.answer_labelled == "fots-reimpl + camera_misalignment (correction of unshown cause)");
  REQUIRE(s.answer_at_bound.size() == 1);
  CHECK(s.answer_at_bound[0].param == "camera_misalignment.scale");
  CHECK(s.answer_at_bound[0].bound == "upper");
  REQUIRE(s.candidates.size() == 1);
  CHECK(s.candidates[0].verdict == "unshown cause");
  // A found effect, and a bad flag.
  j["selected"][0]["fingerprint_found"] = true;
  std::ofstream(path) << j.dump(1);
  CHECK(load_residual_summary(path).candidates[0].verdict == "found");
  j["selected"][0]["fingerprint_found"] = "yes";
  std::ofstream(path) << j.dump(1);
  CHECK_THROWS_WITH(load_residual_summary(path), Catch::Contains("/selected/0/fingerprint_found"));
}

}  // namespace test_residual_view_evidence
