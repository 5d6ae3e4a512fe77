// core/models/model_family: the family registry. Every form resolves to its family and back, builds, and its
// table's defaults lie in their ranges; the policy the rest of the code reads from it (fit stages, corrections,
// held parameters, the precision switch) names parameters the forms have; unknown ids get a did-you-mean.
#include <catch2/catch.hpp>

#include <algorithm>
#include <functional>
#include <set>
#include <stdexcept>
#include <string>

#include "core/calibration/fit.hpp"
#include "core/loop/residual.hpp"
#include "core/models/any_batch.hpp"
#include "core/models/model_family.hpp"
#include "core/sensor/sensor.hpp"
#include "core/workbench/session_file.hpp"

// This file's names in a namespace of its own: the unity build compiles several test files as one unit.
namespace test_model_family {

namespace {

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

bool has_param(const sb::ModelForm& form, const std::string& name) {
  return std::any_of(form.params.begin(), form.params.end(), [&](const sb::ParamSpec& s) { return s.name == name; });
}

}  // namespace

TEST_CASE("model families: every family's ids resolve, once", "[model_family]") {
  std::set<std::string> seen;
  for (const sb::ModelFamily& family : sb::model_families()) {
    CHECK(&sb::model_family(family.id) == &family);
    REQUIRE_FALSE(family.forms.empty());
    CHECK(family.base().kind == sb::FormKind::kPublished);
    for (const sb::ModelForm& form : family.forms) {
      INFO(form.id);
      CHECK(seen.insert(form.id).second);  // no form in two families
      CHECK(&sb::family_of_form(form.id) == &family);
      CHECK(&sb::model_form(form.id) == &form);
      CHECK_FALSE(form.label.empty());
      CHECK(sb::has_batch(form.id));
    }
  }
  // model_ids() is the registry's forms, the published ones first.
  CHECK(seen == std::set<std::string>(sb::model_ids().begin(), sb::model_ids().end()));
  CHECK(sb::model_ids().front() == sb::model_families().front().base().id);
}

TEST_CASE("model families: each form's table has its defaults within range", "[model_family]") {
  for (const sb::ModelFamily& family : sb::model_families())
    for (const sb::ModelForm& form : family.forms) {
      REQUIRE_FALSE(form.params.empty());
      for (const sb::ParamSpec& s : form.params) {
        INFO(form.id << "." << s.name);
        CHECK(s.min <= s.default_value);
        CHECK(s.default_value <= s.max);
        if (s.log_scale) CHECK(s.min > 0);
        if (s.is_switch) CHECK((s.default_value == 0 || s.default_value == 1));
      }
      CHECK(sb::default_params(form.id).size() == form.params.size());
    }
}

TEST_CASE("model families: stages, corrections, holds and switches name what the forms have", "[model_family]") {
  for (const sb::ModelFamily& family : sb::model_families()) {
    for (const sb::ModelForm& form : family.forms) {
      INFO(form.id);
      REQUIRE_FALSE(form.fit_stages.empty());
      for (const sb::FitStage& stage : form.fit_stages)
        for (const std::string& p : stage.params) CHECK(has_param(form, p));
      for (const std::string& p : form.px_scale_params) CHECK(has_param(form, p));
      CHECK(sb::fit_stages(form.id).size() == form.fit_stages.size());
    }
    CHECK(sb::model_form_variants(family.base().id) == family.correction_ids());
    CHECK(sb::model_form_hold(family.base().id) == family.hold);
    for (const std::string& p : family.hold) CHECK(has_param(family.base(), p));
    if (!family.single_precision_switch.empty())
      CHECK(std::any_of(family.forms.begin(), family.forms.end(),
                        [&](const sb::ModelForm& f) { return has_param(f, family.single_precision_switch); }));
    // A correction has no corrections of its own.
    for (const std::string& c : family.correction_ids()) CHECK(sb::model_form_variants(c).empty());
  }
}

TEST_CASE("model families: the session keeps one form per family", "[model_family]") {
  sb::SessionSource open;
  for (const sb::ModelFamily& family : sb::model_families()) CHECK(open.form_shown(family.id) == family.base().id);
}

TEST_CASE("model families: an unknown id names the nearest", "[model_family]") {
  const std::string family = message_of([] { sb::model_family("tacls"); });
  CHECK(family.find("did you mean 'tacsl'") != std::string::npos);
  const std::string form = message_of([] { sb::model_form("fots-reimp"); });
  CHECK(form.find("did you mean 'fots-reimpl'") != std::string::npos);
  CHECK(message_of([] { sb::family_of_form("hydroshear-contakt"); }).find("hydroshear-contact") != std::string::npos);
  CHECK(sb::find_model_form("hydroshear-contact+tool_frame") == nullptr);
  CHECK(sb::find_model_family_of_form("none") == nullptr);
}

}  // namespace test_model_family
