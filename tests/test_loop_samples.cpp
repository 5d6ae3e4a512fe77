// What the residual loop's steps share about samples (core/loop/loop_samples.hpp): the evenly spaced subset the
// search's costly fits see.
#include <catch2/catch.hpp>

#include <vector>

#include "core/loop/loop_samples.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_loop_samples {

TEST_CASE("evenly spaced: n of count samples at floor(i count / n), all of them when n is 0 or too many",
          "[residual]") {
  // 4 of 10: floor(0), floor(2.5), floor(5), floor(7.5) = 0, 2, 5, 7 (the last sample is not forced in: the
  // spacing stays even).
  CHECK(sb::evenly_spaced(10, 4) == std::vector<std::size_t>{0, 2, 5, 7});
  // 250 of 1000 (the TacTip's calibration split): every fourth.
  const auto quarter = sb::evenly_spaced(1000, 250);
  REQUIRE(quarter.size() == 250);
  CHECK(quarter[1] == 4);
  CHECK(quarter.back() == 996);
  CHECK(sb::evenly_spaced(3, 0) == std::vector<std::size_t>{0, 1, 2});
  CHECK(sb::evenly_spaced(3, 3) == std::vector<std::size_t>{0, 1, 2});
  CHECK(sb::evenly_spaced(3, 7) == std::vector<std::size_t>{0, 1, 2});
  CHECK(sb::evenly_spaced(0, 5).empty());
}

TEST_CASE("subset: the samples at the indices, in their order", "[residual]") {
  std::vector<sb::FitSample> samples(4);
  for (std::size_t i = 0; i < samples.size(); ++i) samples[i].id = "s" + std::to_string(i);
  const auto picked = sb::subset(samples, {0, 3});
  REQUIRE(picked.size() == 2);
  CHECK(picked[0].id == "s0");
  CHECK(picked[1].id == "s3");
  CHECK_THROWS_AS(sb::subset(samples, {4}), std::out_of_range);
}

}  // namespace test_loop_samples
