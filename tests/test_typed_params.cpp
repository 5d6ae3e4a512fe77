#include <catch2/catch.hpp>

#include "core/base/typed_params.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_typed_params {

using namespace sb;

namespace {
// A model with a kernel rate, a gain only its extended variant has, and a switch.
struct ToyParams {
  double rate = 0;
  double gain = -1;  // not in the base table: stays at this value
  bool paper = false;
};

const ParamFields<ToyParams>& base_fields() {
  static const ParamFields<ToyParams> fields = {
      {{"rate", "m^-2", 100, 1, 1e4, "kernel rate", true}, &ToyParams::rate},
      {{"paper", "", 0, 0, 1, "the paper's choice"}, &ToyParams::paper},
  };
  return fields;
}

const ParamFields<ToyParams>& extended_fields() {
  static const ParamFields<ToyParams> fields = [] {
    ParamFields<ToyParams> f = base_fields();
    f.push_back({{"gain", "", 2, 0, 10, "gain"}, &ToyParams::gain});
    return f;
  }();
  return fields;
}
}  // namespace

TEST_CASE("typed parameters: a table's specs, its switches, and the values read from a set", "[params]") {
  const std::vector<ParamSpec> specs = specs_of(base_fields());
  REQUIRE(specs.size() == 2);
  CHECK(specs[0].name == "rate");
  CHECK(specs[0].log_scale);
  CHECK_FALSE(specs[0].is_switch);
  CHECK(specs[1].is_switch);  // bound to a bool
  ParamSet p(specs);
  p.set("rate", 250);
  p.set("paper", 1);
  const ToyParams v = read_params(base_fields(), p);
  CHECK(v.rate == 250);
  CHECK(v.paper);
  CHECK(v.gain == -1);  // the base variant has no gain: the struct's value stays
  // A switch is on from 0.5 (a slider or a JSON file may give any value in [0, 1]).
  p.set("paper", 0.49);
  CHECK_FALSE(read_params(base_fields(), p).paper);
  p.set("paper", 0.5);
  CHECK(read_params(base_fields(), p).paper);
}

TEST_CASE("typed parameters: the extended table reads its own field, a foreign set throws", "[params]") {
  ParamSet ext(specs_of(extended_fields()));
  CHECK(read_params(extended_fields(), ext).gain == 2);  // the spec's default
  ext.set("gain", 7.5);
  CHECK(read_params(extended_fields(), ext).gain == 7.5);
  // A set built from another table names a parameter the base table does not describe.
  CHECK_THROWS_WITH(read_params(base_fields(), ext), Catch::Contains("'gain' is not in the table"));
}

}  // namespace test_typed_params
