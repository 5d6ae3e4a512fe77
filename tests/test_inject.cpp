// Effects put into data (core/loop/inject.hpp): the rest grid a dataset records under an injected lens.
#include <catch2/catch.hpp>

#include "core/loop/inject.hpp"
#include "core/loop/rest_grid_lens.hpp"
#include "core/sensor/sensor.hpp"

namespace test_inject {

using sb::Vec2;

// A lens bends the recorded rest grid as it bends everything it images: each rest position through
// lens_distort_px. At the principal point the radius is 0 and nothing moves; a corner marker moves by the k1 term.
TEST_CASE("recorded_rest_px bends the rest grid through an injected lens only", "[inject]") {
  const sb::Sensor sensor = sb::make_default_sensor();
  const sb::Camera& camera = sensor.camera;
  const std::vector<Vec2> rest = {camera.principal_px, sensor.markers_rest_px.front(), sensor.markers_rest_px.back()};
  const auto bent = sb::recorded_rest_px(camera, "lens_distortion", {{"k1", -0.15}}, rest);
  REQUIRE(bent.size() == rest.size());
  constexpr double kExact = 1e-12;
  CHECK((bent[0] - rest[0]).norm() <= kExact);
  for (std::size_t j = 1; j < rest.size(); ++j) {
    CHECK((bent[j] - sb::lens_distort_px(camera, -0.15, rest[j])).norm() <= kExact);
    // Barrel (k1 < 0): the corner moves towards the principal point.
    CHECK((bent[j] - camera.principal_px).norm() < (rest[j] - camera.principal_px).norm());
  }
  CHECK(sb::recorded_rest_px(camera, "viscoelastic_creep", {{"tau_s", 0.3}}, rest) == rest);
  CHECK(sb::recorded_rest_px(camera, "lens_distortion", {}, rest) == rest);  // the default k1 is 0
}

}  // namespace test_inject
