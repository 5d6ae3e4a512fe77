// The residual loop's effect search (core/loop/effect_search.hpp): which of a round's candidates keep their joint
// refit. The whole search runs in tests/test_residual.cpp and tests/test_residual_hard.cpp.
#include <catch2/catch.hpp>

#include <vector>

#include "core/loop/effect_search.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_effect_search {

TEST_CASE("joint refit ranks: the promising candidates by their alone RMSE, best first, ties in candidate order",
          "[residual]") {
  // Five candidates; the fourth is not in the ranking (screened alone, or refitted on a found fingerprint whatever
  // its rank). Among the rest the alone RMSEs 3.0, 2.0, 2.5 and 2.0 px order as 2.0 (2nd candidate), 2.0 (5th:
  // a tie keeps candidate order), 2.5, 3.0.
  const std::vector<double> rmse = {3.0, 2.0, 2.5, 1.0, 2.0};
  const std::vector<bool> in_ranking = {true, true, true, false, true};
  CHECK(sb::joint_refit_ranks(rmse, in_ranking) == std::vector<std::size_t>{4, 1, 3, 0, 2});
  CHECK(sb::joint_refit_ranks({}, {}).empty());
  CHECK(sb::joint_refit_ranks({1.0, 2.0}, {false, false}) == std::vector<std::size_t>{0, 0});
}

}  // namespace test_effect_search
