// core/calibration/stage_losses: the fit's cost per stage, each stage relative to its own start.
#include <catch2/catch.hpp>

#include <cmath>

#include "core/calibration/stage_losses.hpp"

namespace test_stage_losses {

TEST_CASE("costs reported under one stage name form one run; a change of name starts the next", "[stage_losses]") {
  std::vector<sb::StageLosses> curve;
  sb::append_stage_loss(curve, "contact", 200);
  sb::append_stage_loss(curve, "contact", 184);
  sb::append_stage_loss(curve, "joint", 4560);
  sb::append_stage_loss(curve, "joint", 3000);
  sb::append_stage_loss(curve, "contact", 150);  // the same name again after another stage: a third run
  REQUIRE(curve.size() == 3);
  CHECK(curve[0].stage == "contact");
  CHECK(curve[0].costs == std::vector<float>{200, 184});
  CHECK(curve[1].stage == "joint");
  CHECK(curve[1].costs == std::vector<float>{4560, 3000});
  CHECK(curve[2].costs == std::vector<float>{150});
}

TEST_CASE("a stage's costs relative to its start begin at 1 whatever the stage's own scale", "[stage_losses]") {
  // 4560 -> 3420 -> 1140 is 1, 3420/4560 = 0.75, 1140/4560 = 0.25: a stage that starts far above the last one's
  // end still starts at 1 and falls, which is what the stage did.
  constexpr float kTol = 1e-6f;
  const std::vector<float> rel = sb::relative_to_stage_start({"joint", {4560, 3420, 1140}});
  REQUIRE(rel.size() == 3);
  CHECK(rel[0] == 1.0f);
  CHECK(std::abs(rel[1] - 0.75f) < kTol);
  CHECK(std::abs(rel[2] - 0.25f) < kTol);
}

TEST_CASE("a stage that starts at zero cost reads 1, not a division by zero", "[stage_losses]") {
  const std::vector<float> rel = sb::relative_to_stage_start({"s", {0, 0}});
  CHECK(rel == std::vector<float>{1, 1});
  CHECK(sb::relative_to_stage_start({"s", {}}).empty());
}

}  // namespace test_stage_losses
