// The hard case of the residual loop: one catalogued effect injected, undeclared, into the
// *measured* fields of a finite-element twin set (../shared/data/twin), whose physics none of the models
// reproduces exactly, then the whole loop (base fitted, every catalogued effect a candidate). The easy
// case (tests/test_residual.cpp) injects into a model's own output, where the base is exact.
//
// Injection modifies the measurement the way the effect would have: creep filters each marker's measured
// series through the standard linear solid, lens distortion maps the measured displacement through the
// lens, subsurface markers smooth the measured field. The FE twin is quasi-static and rate-independent,
// so a hold inserted at peak load (the peak frame's pose and field repeated) is what the FE would give
// for a held press; creep needs it to show (the twin presses are not held).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <random>

#include "core/base/data_root.hpp"
#include "core/calibration/fit_data.hpp"
#include "core/effects/effects.hpp"
#include "core/loop/inject.hpp"
#include "core/loop/residual.hpp"
#include "core/loop/residual_report.hpp"
#include "core/loop/rest_grid_lens.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_residual_hard {

using sb::FitSample;
using sb::Vec2;

namespace {

// Main parameters must be recovered within 30 % (the criterion).
constexpr double kMainParamRelTol = 0.30;
constexpr int kHoldFrames = 50;        // 1 s at the twin's 0.02 s frames
constexpr int kPerMotion = 1;          // samples per motion and split: the CI slice
constexpr double kTwinNoisePx = 0.05;  // the twin sets' tracking noise (dataset.json provenance)

std::string data_root() {
  const char* env = std::getenv("SHEARBENCH_DATA");
  return env ? env : sb::resolve_data_root("");
}

struct TwinSlice {
  std::shared_ptr<const sb::Sensor> sensor;
  std::vector<FitSample> calibration, validation;
};

// The first kPerMotion samples of each motion in each split of twin set `name`.
TwinSlice load_twin(const std::string& name) {
  const std::string dir = data_root() + "/twin/" + name;
  if (!std::filesystem::is_directory(dir)) FAIL("needs the twin set " << dir << " (set SHEARBENCH_DATA)");
  const sb::Dataset ds = sb::read_dataset(dir);
  TwinSlice t;
  t.sensor = sb::dataset_sensor(ds);
  const auto indenters = sb::dataset_indenters(ds, data_root());
  std::map<std::string, int> taken;
  for (const auto& info : ds.samples) {
    if (taken[info.split + "/" + info.motion]++ >= kPerMotion) continue;
    FitSample s = sb::to_fit_sample(info, sb::read_sample(ds, info.id), indenters.at(info.indenter));
    (info.split == "calibration" ? t.calibration : t.validation).push_back(std::move(s));
  }
  return t;
}

// A held press of the quasi-static twin (core/loop/inject.hpp), with the twin's tracking noise.
void insert_hold(const sb::Sensor& sensor, FitSample* s, std::mt19937_64* rng) {
  sb::insert_hold(sensor, kHoldFrames, kTwinNoisePx, rng, s);
}

// Applies `effect` at `params` to the measured series of every sample (core/loop/inject.hpp).
void inject(const sb::Sensor& sensor, const std::string& effect, const std::map<std::string, double>& params,
            std::vector<FitSample>* samples) {
  for (auto& s : *samples) sb::inject_effect(sensor, effect, params, &s);
}

// The sensor as the dataset records it: a lens images the printed rest grid bent too (markers_rest_px =
// D(rest)); p_EM stays, the markers are physically where they are. The injection above used the unbent
// sensor: D(m + d) - D(m) about the true rest m (the effect, given the recorded D(m), differs at second order).
std::shared_ptr<const sb::Sensor> recorded_sensor(const std::shared_ptr<const sb::Sensor>& sensor,
                                                  const std::string& effect,
                                                  const std::map<std::string, double>& params) {
  if (effect != "lens_distortion") return sensor;
  auto bent = std::make_shared<sb::Sensor>(*sensor);
  bent->markers_rest_px = sb::recorded_rest_px(bent->camera, effect, params, bent->markers_rest_px);
  return bent;
}

// The options of the nuisance-effect cases: the model-form round off (it has its own cases below).
sb::ResidualOptions nuisance_options() {
  sb::ResidualOptions o;
  o.max_iterations = 15;
  o.model_forms = false;
  return o;
}

sb::ResidualReport run_hard(const std::string& model, const std::string& set, const std::string& effect,
                            const std::map<std::string, double>& params,
                            const sb::ResidualOptions& o = nuisance_options()) {
  TwinSlice t = load_twin(set);
  std::mt19937_64 rng(16);
  if (effect == "viscoelastic_creep")
    for (auto* split : {&t.calibration, &t.validation})
      for (auto& s : *split) insert_hold(*t.sensor, &s, &rng);
  if (!effect.empty()) {
    inject(*t.sensor, effect, params, &t.calibration);
    inject(*t.sensor, effect, params, &t.validation);
  }
  sb::ResidualInputs in;
  in.dataset = set + (effect.empty() ? "" : "+" + effect);
  in.model_id = model;
  in.sensor = recorded_sensor(t.sensor, effect, params);
  in.base_params = sb::default_params(model);
  in.calibration = std::move(t.calibration);
  in.validation = std::move(t.validation);
  return sb::run_residual_loop(in, o);
}

// The loop on a twin slice for HydroShear with the model-form round and one cheap effect candidate (the
// effect rounds are not what these tests are about).
sb::ResidualReport run_model_forms(TwinSlice t) {
  sb::ResidualInputs in;
  in.dataset = "twin_sphere35 slice";
  in.model_id = "hydroshear";
  in.sensor = t.sensor;
  in.base_params = sb::default_params("hydroshear");
  in.calibration = std::move(t.calibration);
  in.validation = std::move(t.validation);
  sb::ResidualOptions o;
  o.max_iterations = 15;
  o.candidates = {"tracker_bias"};
  return sb::run_residual_loop(in, o);
}

void check_hard(const std::string& model, const std::string& set, const std::string& effect,
                const std::string& main_param, double value, const std::map<std::string, double>& params) {
  const auto r = run_hard(model, set, effect, params);
  const auto j = sb::residual_to_json(r);
  INFO(j["before"].dump(1));
  INFO(j["rounds"].dump(1));
  REQUIRE(!r.effects.selection.selected.empty());
  CHECK(r.effects.selection.selected.front() == effect);
  // The answer's evidence (core/loop/effect_evidence.hpp): the injected effect is found by it, nothing else is.
  REQUIRE(r.evidence.size() == r.effects.selection.selected.size());
  for (const auto& e : r.evidence) {
    INFO(e.effect << ": " << e.verdict);
    CHECK(e.found == (e.effect == effect));
  }
  const double fitted = r.after.fit.params.get(effect + "." + main_param);
  INFO(effect << "." << main_param << ": fitted " << fitted << ", injected " << value);
  CHECK(std::abs(fitted - value) <= kMainParamRelTol * std::abs(value));
}

// Creep: tau 0.3 s, 30 % creep (the field grows by 26 % over a 1 s hold and leaves 0.3 x 97 % behind at release).
const std::map<std::string, double> kCreep = {{"tau_s", 0.3}, {"creep_fraction", 0.3}};
// Lens: k1 = -0.15 moves a corner marker (r = 0.75) by 8 % of its displacement.
const std::map<std::string, double> kLens = {{"k1", -0.15}};
// Subsurface: markers 1 mm deep (a fifth of the 4.5 mm gel), no attenuation.
const std::map<std::string, double> kSubsurface = {{"depth_m", 0.001}};

}  // namespace

// Creep's fingerprint (core/loop/fingerprints.hpp) is the change of the measured field while the pose is held
// and after release, which no rate-independent model's form error can produce: tau and c are estimated from it
// alone (the SLS undone) and held there while the base is refitted; the candidate must explain the validation
// drift (or pass the interval) and not make the whole field certainly worse. Found for all three models.
TEST_CASE("hard case: undeclared creep in FE twin data is selected and its tau recovered", "[residual_hard][slow]") {
  const std::string model = GENERATE(as<std::string>{}, "fots-reimpl", "tacsl", "hydroshear");
  check_hard(model, "twin_sphere35", "viscoelastic_creep", "tau_s", 0.3, kCreep);
}

// The lens's fingerprint is the rest grid (core/loop/rest_grid_lens.hpp): the printed lattice the dataset records,
// bent by the lens about the principal point, which no contact model touches. k1 is read there, held while the
// base is refitted, and the candidate is accepted on that evidence (the whole-field change is the base's form:
// HydroShear + the true lens is 3.3 % worse on validation than HydroShear alone). (The residual's asymmetry about the
// contact, the fingerprint before, read the FE pad's own asymmetry too: 0.03 / -0.14 with FOTS re-impl. for the
// injected -0.15, 0.24 / 0.01 on the untouched set; it is kept only for rest grids that are not a lattice.)
// Release, 2 shared cores: 10.5 s (FOTS re-impl.), 6.4 s (TacSL), 6.1 s (HydroShear).
TEST_CASE("hard case: undeclared lens distortion in FE twin data is selected and k1 recovered",
          "[residual_hard][slow]") {
  const std::string model = GENERATE(as<std::string>{}, "fots-reimpl", "tacsl", "hydroshear");
  check_hard(model, "twin_sphere35", "lens_distortion", "k1", -0.15, kLens);
}

// Markers below the surface low-pass the field on the marker grid, and so does a model whose field is
// smoother than the gel's, while a sharper model reads as depth: the fine-scale fingerprint reads 2.0-2.1 mm
// (FOTS re-impl.), 1.1-1.4 mm (TacSL) and 0 (HydroShear) with or without 1 mm injected. No evidence outside the
// displacement field tells them apart, so the reading counts only where the model, smoothed, explains the
// measured field's grid-scale content down to the tracker noise (1.0x the noise's with the model exact,
// test_residual.cpp). On the FE twin every model leaves 100-150x: the loop must report the depth as read
// against a model wrong at the grid scale and select nothing (before this rule FOTS re-impl. took 4.9 mm for
// 3 mm injected, and TacSL 1.5 mm on the untouched twin_sphere8). Release, 2 cores: about 25 s for the three.
TEST_CASE("hard case: subsurface markers under a model wrong at the grid scale are reported, not selected",
          "[residual_hard][slow]") {
  const std::string model = GENERATE(as<std::string>{}, "fots-reimpl", "tacsl", "hydroshear");
  const auto r = run_hard(model, "twin_sphere35", "subsurface_markers", kSubsurface);
  const auto j = sb::residual_to_json(r);
  INFO(model << ": " << j["rounds"].dump(1));
  for (const auto& id : r.effects.selection.selected) CHECK(id != "subsurface_markers");
  // Whatever else is selected is a correction of unshown cause: the set holds no other effect.
  for (const auto& e : r.evidence) {
    INFO(e.effect << ": " << e.verdict);
    CHECK_FALSE(e.found);
  }
  const auto& first_round = j["rounds"].at(0);
  bool reported = false;
  for (const auto& c : first_round)
    if (c["effect"] == "subsurface_markers") {
      reported = true;
      CHECK_FALSE(c["accepted"].get<bool>());
      const std::string verdict = c["fingerprint"]["verdict"];
      // HydroShear's Gaussian kernel is smoother than the FE field: it reads no depth at all.
      if (model == "hydroshear")
        CHECK(verdict.find("not smoother than the model's") != std::string::npos);
      else
        CHECK(verdict.find("wrong at the grid scale") != std::string::npos);
    }
  CHECK(reported);
}

// The untouched twin set holds none of the nuisance effects: the loop must not select any of them (before
// the bound verdict and the screen it selected load_stiffening + viscoelastic_creep on twin_sphere35).
TEST_CASE("hard case: untouched FE twin data select no nuisance effect", "[residual_hard][slow]") {
  const std::string model = GENERATE(as<std::string>{}, "fots-reimpl", "tacsl", "hydroshear");
  const auto r = run_hard(model, "twin_sphere35", "", {});
  INFO(model << ": " << sb::residual_to_json(r)["rounds"].dump(1));
  int nuisance = 0;
  for (const auto& id : r.effects.selection.selected)
    nuisance += id == "viscoelastic_creep" || id == "lens_distortion" || id == "subsurface_markers";
  CHECK(nuisance == 0);
  // Nothing is found: a selected correction (tool_frame on the whole set) is labelled a correction of unshown cause.
  REQUIRE(r.evidence.size() == r.effects.selection.selected.size());
  for (const auto& e : r.evidence) {
    INFO(e.effect << ": " << e.verdict);
    CHECK_FALSE(e.found);
  }
}

// The former false positive: TacSL on the untouched twin_sphere8 selected subsurface markers (1.53 mm, +13 %),
// its per-point field sharper than the gel's. Its fingerprint still reads about a millimetre there, at 70x the
// noise's grid-scale content: reported, not selected.
TEST_CASE("hard case: TacSL on the untouched twin_sphere8 selects no subsurface markers", "[residual_hard][slow]") {
  const auto r = run_hard("tacsl", "twin_sphere8", "", {});
  const auto j = sb::residual_to_json(r);
  INFO(j["rounds"].dump(1));
  CHECK(std::find(r.effects.selection.selected.begin(), r.effects.selection.selected.end(), "subsurface_markers") ==
        r.effects.selection.selected.end());
  int reported = 0;
  for (const auto& c : j["rounds"].at(0))
    if (c["effect"] == "subsurface_markers") {
      ++reported;
      CHECK(c["fingerprint"]["verdict"].get<std::string>().find("wrong at the grid scale") != std::string::npos);
    }
  CHECK(reported == 1);
}

// The model-form round where the base model is wrong: the FE gel's stick zone moves with the
// indenter and its layer has a near field (docs/effects.md), which HydroShear's one-Gaussian linear sum
// lacks. Fitted on the calibration slice, one of its variants must pass the held-out rule and lower the
// validation RMSE by at least kMinModelFormGainPct (on the whole set: 2.12 -> 0.745 px, 65 %, hydroshear-contact).
constexpr double kMinModelFormGainPct = 10.0;
// Issue 31: the effects are looked for on the model form the loop selected, and the answer is the two together.
// Creep injected into the FE twin (whose contact HydroShear's form gets wrong): the model-form round selects a
// variant, creep is then found on top of it from its fingerprint, and the final model, form + creep fitted
// jointly, must score lower than the form alone and than HydroShear + creep (the loop without the model-form
// round), with tau within kAnswerTauRelTol of the injected value.
constexpr double kAnswerTauRelTol = 0.10;
sb::ResidualReport run_creep(bool model_forms) {
  sb::ResidualOptions o = nuisance_options();
  o.model_forms = model_forms;
  o.candidates = {"viscoelastic_creep", "tracker_bias"};
  return run_hard("hydroshear", "twin_sphere35", "viscoelastic_creep", kCreep, o);
}

TEST_CASE("hard case: creep under a wrong model form: the answer is the selected form plus creep",
          "[residual_hard][slow]") {
  const auto r = run_creep(true);
  const auto j = sb::residual_to_json(r);
  INFO(j["model_forms"].dump(1));
  INFO(j["rounds"].dump(1));
  // The model-form round: a variant passes the held-out rule and lowers the error by at least
  // kMinModelFormGainPct; kept with its dilation kernel held only when held-out data preferred that fit.
  REQUIRE(r.model_form.scores.size() == sb::model_form_variants("hydroshear").size());
  REQUIRE_FALSE(r.model_form.selected.empty());
  const double base = sb::validation_rmse(r.before.fit.validation);
  const double form = sb::validation_rmse(r.model_form.fits.at(r.model_form.selected).fit.validation);
  CHECK(form < (1 - kMinModelFormGainPct / 100) * base);
  CHECK(j["model_form_selected"] == r.model_form.selected);
  if (!r.model_form.held.empty()) CHECK(form < r.model_form.joint_rmse_px);
  // Issue 31: the effects are looked for on that form, and the answer is the two together.
  CHECK(r.effects.form == r.model_form.selected);
  REQUIRE(r.effects.selection.selected == std::vector<std::string>{"viscoelastic_creep"});
  CHECK(r.after_model == r.model_form.selected + "+viscoelastic_creep");
  CHECK(j["after_model"] == r.after_model);
  const double answer = sb::validation_rmse(r.after.fit.validation);
  const auto base_creep = run_creep(false);
  REQUIRE(base_creep.after_model == "hydroshear+viscoelastic_creep");
  const double creep_alone = sb::validation_rmse(base_creep.after.fit.validation);
  INFO("base " << base << " px, answer " << answer << " px, form alone " << form << " px, hydroshear + creep "
               << creep_alone << " px");
  CHECK(answer < form);
  CHECK(answer < creep_alone);
  const double tau = r.after.fit.params.get("viscoelastic_creep.tau_s");
  INFO("tau " << tau << " s, injected " << kCreep.at("tau_s"));
  CHECK(std::abs(tau - kCreep.at("tau_s")) <= kAnswerTauRelTol * kCreep.at("tau_s"));
  // The report says the same: its answer and its before / after table are the final model's.
  const std::string md = sb::residual_to_markdown(r, {});
  CHECK_THAT(md, Catch::Contains("The loop's answer: `" + r.after_model + "`"));
  CHECK_THAT(md, Catch::Contains("After: " + r.after_model));
}

// Where the base is exact (the twin slice's poses, HydroShear's own field plus tracker noise), no variant may
// pass: each can reproduce the base (beta_s = 0, stick_sat = 0, beta_s3 = 0, follow = 0) but has nothing more
// to explain.
TEST_CASE("model-form round: HydroShear's own field selects no variant", "[residual_hard][slow]") {
  TwinSlice t = load_twin("twin_sphere35");
  std::mt19937_64 rng(17);
  std::normal_distribution<double> noise(0.0, kTwinNoisePx);
  for (auto* split : {&t.calibration, &t.validation})
    for (auto& s : *split) {
      auto m = sb::make_model("hydroshear", t.sensor, s.indenter);
      s.meas_px = sb::simulate_sample(*m, s);
      for (auto& frame : s.meas_px)
        for (auto& d : frame) {
          const double dx = noise(rng);  // sequenced: argument order is unspecified
          d += Vec2(dx, noise(rng));
        }
    }
  const auto r = run_model_forms(std::move(t));
  INFO(sb::residual_to_json(r)["model_forms"].dump(1));
  CHECK(r.model_form.selected.empty());
}

}  // namespace test_residual_hard
