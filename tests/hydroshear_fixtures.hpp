#pragma once
// The path of the HydroShear variant tests (stick zone, contact): a 6 mm box pressed 0.4 mm, slid
// 0.32 mm and twisted 0.04 rad (stick and slip, shear and dilation; the box covers markers), and the
// field of a batch at its end.
#include <memory>
#include <span>
#include <vector>

#include "core/models/hydroshear.hpp"
#include "model_fixtures.hpp"

namespace sbtest {

inline constexpr double kHsBoxSide = 6e-3;

inline std::vector<Pose> hs_box_path() {
  const double a = kHsBoxSide;
  return {box_pose(a, 0, 0, 0.1e-3), box_pose(a, 0, 0, -0.4e-3), box_pose(a, 0.3e-3, 0.1e-3, -0.4e-3),
          box_pose(a, 0.3e-3, 0.1e-3, -0.4e-3, 0.04)};
}

inline std::shared_ptr<const Indenter> hs_box() {
  static const auto b = box_indenter(kHsBoxSide, 7, 0.8e-3);
  return b;
}

inline std::vector<Vec2> hs_path_field(HydroShearBatch& batch) {
  std::vector<Vec2> disp(batch.markers());
  for (const Pose& X : hs_box_path()) batch.step(std::span<const Pose>(&X, 1), 0.01, disp, {});
  return disp;
}

inline std::vector<Vec2> hs_path_field(const ParamSet& p, std::shared_ptr<const Sensor> sensor = test_sensor()) {
  HydroShearBatch batch(std::move(sensor), hs_box(), 1, p);
  return hs_path_field(batch);
}

}  // namespace sbtest
