// The penetration remembered across models (core/effects/penetration_cache.hpp): the same value as computed, and
// nothing kept for an indenter that is gone.
#include <catch2/catch.hpp>

#include "core/effects/penetration_cache.hpp"
#include "tests/model_fixtures.hpp"

namespace test_penetration_cache {

using namespace sb;
using namespace sbtest;

TEST_CASE("cached_penetration is indenter_penetration, remembered per exact pose and dropped with its indenter",
          "[penetration_cache]") {
  const auto sensor = test_sensor();
  const std::size_t before = penetration_cache_size();
  {
    const auto sphere = sphere_indenter(4e-3);
    Pose X = Pose::Identity();
    X.translation() = Vec3(1e-3, -0.5e-3, 4e-3 - 0.7e-3);  // 0.7 mm into the gel
    const Penetration direct = indenter_penetration(*sensor->gel_sdf, *sphere, X);
    const Penetration first = cached_penetration(sensor, sphere, X);
    const Penetration again = cached_penetration(sensor, sphere, X);
    CHECK(direct.penetrating);
    for (const Penetration* p : {&first, &again}) {
      CHECK(p->depth_m == direct.depth_m);  // bit for bit: the same function of the same arguments
      CHECK(p->centre_E == direct.centre_E);
      CHECK(p->radius_m == direct.radius_m);
    }
    CHECK(penetration_cache_size() == before + 1);
    // The least change of the pose is another pose: computed, not confused with the first.
    Pose Y = X;
    Y.translation().z() = std::nextafter(X.translation().z(), 1.0);
    CHECK(cached_penetration(sensor, sphere, Y).depth_m == indenter_penetration(*sensor->gel_sdf, *sphere, Y).depth_m);
    CHECK(penetration_cache_size() == before + 2);
    // Another indenter is another pair: the same pose, its own value (a 2 mm sphere at the 4 mm one's height).
    const auto small = sphere_indenter(2e-3);
    CHECK(cached_penetration(sensor, small, X).depth_m == indenter_penetration(*sensor->gel_sdf, *small, X).depth_m);
    CHECK(cached_penetration(sensor, small, X).depth_m != first.depth_m);
  }
  // Both indenters are gone: their entries no longer count, and the next lookup drops them.
  CHECK(penetration_cache_size() == before);
}

}  // namespace test_penetration_cache
