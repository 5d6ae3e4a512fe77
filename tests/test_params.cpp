#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "core/base/error.hpp"
#include "core/base/params.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_params {

using namespace sb;

namespace {
ParamSet two_params() {
  return ParamSet({{"mu", "", 0.5, 0.0, 5.0, "friction ratio"}, {"lambda_s", "m^-2", 10800, 100, 1e6, "kernel", true}});
}
}  // namespace

TEST_CASE("a parameter table starts at its defaults and round-trips through JSON", "[params]") {
  ParamSet p = two_params();
  CHECK(p.get("mu") == 0.5);
  p.set("mu", 0.7);
  const auto j = p.to_json();
  ParamSet q = two_params();
  q.update_from_json(j, "params.json");
  CHECK(q.get("mu") == 0.7);
  CHECK(q.get("lambda_s") == 10800);
}

TEST_CASE("out-of-range, unknown and non-numeric parameters are rejected with the file", "[params]") {
  ParamSet p = two_params();
  CHECK_THROWS_AS(p.set("mu", 6.0), std::invalid_argument);
  CHECK_THROWS_AS(p.set("mu", NAN), std::invalid_argument);
  CHECK_THROWS_AS(p.get("nope"), std::out_of_range);
  CHECK_THROWS_WITH(p.update_from_json(nlohmann::json{{"nope", 1}}, "P.json"), Catch::Contains("P.json"));
  CHECK_THROWS_WITH(p.update_from_json(nlohmann::json{{"mu", "x"}}, "P.json"), Catch::Contains("not a number"));
  CHECK(p.get("mu") == 0.5);  // a rejected value changes nothing
}

}  // namespace test_params
