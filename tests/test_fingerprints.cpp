// The fingerprint registry (core/loop/fingerprints.hpp): one entry per fingerprinted effect, keyed by the
// effect catalogue's ids.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "core/loop/fingerprints.hpp"
#include "tests/fingerprint_series.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_fingerprints {

using fingerprint_series::add_noise;
using fingerprint_series::apply_effect;
using fingerprint_series::sensor;
using fingerprint_series::Series;
using sb::FingerprintSample;
using sb::Vec2;

// The registry is keyed by catalogue ids: a key that names no effect (a typo) would never be asked for.
TEST_CASE("every fingerprint in the registry belongs to a catalogued effect", "[fingerprint]") {
  const std::vector<std::string>& catalogue = sb::effect_ids();
  const std::vector<std::string> keys = sb::fingerprinted_effects();
  CHECK(keys == std::vector<std::string>{"viscoelastic_creep", "lens_distortion", "subsurface_markers"});
  for (const std::string& id : keys) {
    INFO(id);
    CHECK(std::find(catalogue.begin(), catalogue.end(), id) != catalogue.end());
    CHECK(sb::has_fingerprint(id));
  }
  CHECK_FALSE(sb::has_fingerprint("dome_sway"));
  CHECK_FALSE(sb::fingerprint_needs_model("dome_sway", sensor()));
  CHECK_FALSE(sb::fingerprint_check("dome_sway", sensor(), {}, {}).has_value());
}

}  // namespace test_fingerprints
