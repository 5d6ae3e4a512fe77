// Models by name (core/effects/model_spec.hpp): a model form followed by catalogued effects, the residual
// loop's answer as every command loads it.
#include <catch2/catch.hpp>

#include <stdexcept>

#include "core/calibration/fit.hpp"
#include "core/calibration/param_sets.hpp"
#include "core/effects/effects.hpp"
#include "core/effects/model_spec.hpp"
#include "model_fixtures.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_model_spec {

using namespace sb;

TEST_CASE("model spec: a form and its effects by name, checked part by part", "[model_spec]") {
  const ModelSpec s = parse_model_spec("hydroshear-contact+viscoelastic_creep+lens_distortion");
  CHECK(s.form == "hydroshear-contact");
  CHECK(s.effects == std::vector<std::string>{"viscoelastic_creep", "lens_distortion"});
  CHECK(s.id() == "hydroshear-contact+viscoelastic_creep+lens_distortion");
  CHECK(parse_model_spec("tacsl").effects.empty());
  CHECK_THROWS_WITH(parse_model_spec("hydroshear+wobble"), Catch::Contains("unknown effect 'wobble'"));
  CHECK_THROWS_WITH(parse_model_spec("nosuch+viscoelastic_creep"), Catch::Contains("unknown model id 'nosuch'"));
  CHECK_THROWS_WITH(parse_model_spec("hydroshear++lens_distortion"), Catch::Contains("empty name"));
  CHECK_THROWS_WITH(parse_model_spec("hydroshear+lens_distortion+lens_distortion"), Catch::Contains("named twice"));
}

TEST_CASE("model spec: the table is the form's then each effect's, and the model is the form wrapped", "[model_spec]") {
  const ParamSet form = default_params("hydroshear-contact");
  const ParamSet p = model_spec_params("hydroshear-contact+viscoelastic_creep");
  const ParamSet creep = make_effect("viscoelastic_creep")->params();
  REQUIRE(p.size() == form.size() + creep.size());
  for (std::size_t i = 0; i < form.size(); ++i) CHECK(p.specs()[i].name == form.specs()[i].name);
  CHECK(p.specs()[form.size()].name == "viscoelastic_creep." + creep.specs()[0].name);
  const auto sensor = sbtest::test_sensor();
  const auto sphere = sbtest::sphere_indenter(0.004);
  auto model = make_spec_model("hydroshear-contact+viscoelastic_creep", sensor, sphere);
  CHECK(model->id() == "hydroshear-contact+viscoelastic_creep");
  CHECK(make_spec_model("fots", sensor, sphere)->id() == "fots");
}

TEST_CASE("model spec: its fit stages are the form's, then one stage of the effects' free parameters", "[model_spec]") {
  const auto form = fit_stages("hydroshear");
  const auto both = fit_stages("hydroshear+tracker_bias");
  REQUIRE(both.size() == form.size() + 1);
  CHECK(both.back().name == "effects");
  // tracker_bias has gain, bias_x_px, bias_y_px and moving_threshold_px; the threshold is held (it makes the
  // output discontinuous), so three are fitted.
  CHECK(both.back().params ==
        std::vector<std::string>{"tracker_bias.gain", "tracker_bias.bias_x_px", "tracker_bias.bias_y_px"});
  const auto joint = joint_stage("hydroshear+tracker_bias", false).params;
  CHECK(joint.size() == joint_stage("hydroshear", false).params.size() + 3);
}

TEST_CASE("model spec: a parameter set gives a form with effects its form's fitted values", "[model_spec]") {
  NamedParamSet set;
  set.name = "test";
  set.tables["hydroshear-contact"] = {{"mu", 0.7}};
  set.tables["hydroshear-contact+viscoelastic_creep"] = {{"viscoelastic_creep.tau_s", 0.4}};
  const ParamSet p = set.params("hydroshear-contact+viscoelastic_creep");
  CHECK(p.get("mu") == 0.7);                        // the form's table
  CHECK(p.get("viscoelastic_creep.tau_s") == 0.4);  // the model's own table on top
  CHECK(set.params("hydroshear-contact+lens_distortion").get("mu") == 0.7);
}

}  // namespace test_model_spec
