// The evidence registry (core/loop/effect_evidence.hpp) and the rule every reader shares (core/loop/evidence.hpp).
#include <catch2/catch.hpp>

#include <algorithm>

#include "core/effects/effects.hpp"
#include "core/loop/effect_evidence.hpp"

namespace test_effect_evidence {

// Every catalogued effect has a reader, and the readers are the catalogue's (a misspelt id fails here).
TEST_CASE("effect evidence: one reader per catalogued effect", "[evidence]") {
  auto readers = sb::evidenced_effects();
  auto catalogue = sb::effect_ids();
  std::sort(readers.begin(), readers.end());
  std::sort(catalogue.begin(), catalogue.end());
  CHECK(readers == catalogue);
  CHECK_THROWS_AS(sb::evidence_needs_marker_depth("wobble"), std::invalid_argument);
}

// The rule, by hand: readings 1.0 +- 0.1 and 1.2 +- 0.1 are 10 and 12 standard errors out, one sign, ratio 1.2 <
// 1.5: found. A split at 0.25 +- 0.1 is within 3 standard errors; 1.0 and 2.0 disagree (ratio 2); a fitted value
// of the other sign contradicts the evidence.
TEST_CASE("effect evidence: the rule", "[evidence]") {
  const auto judge = [](double a, double b, double fitted) {
    sb::EffectEvidence e;
    e.quantity = "q";
    e.fitted = fitted;
    e.calibration.estimate = a, e.calibration.std_error = 0.1, e.calibration.samples = 5;
    e.validation.estimate = b, e.validation.std_error = 0.1, e.validation.samples = 5;
    sb::conclude_evidence(&e);
    return e;
  };
  CHECK(judge(1.0, 1.2, 1.0).found);
  CHECK_FALSE(judge(1.0, 0.25, 1.0).found);
  CHECK_FALSE(judge(1.0, 2.0, 1.0).found);
  CHECK_FALSE(judge(1.0, 1.2, -1.0).found);
  CHECK_THAT(judge(1.0, 1.2, -1.0).verdict, Catch::Contains("opposite sign"));
  // Fewer than three samples carry no scatter to judge by.
  const sb::SplitReading r = sb::reading_of({1.0, 1.1}, "press");
  CHECK_FALSE(r.missing.empty());
}

}  // namespace test_effect_evidence
