// tool_frame: the robot's tool frame is not where the recorded poses assume: it tilts the sensor about a point
// below the skin's apex, and its zero (the depth it counts presses from) is not at the skin. A pose effect: it
// corrects the indenter's pose before the base model sees it.
#include "core/effects/effect_catalogue.hpp"

namespace sb::effects {
namespace {

struct ToolFrameParams {
  double pivot_depth_m = 0, press_offset_m = 0;
};

const ParamFields<ToolFrameParams>& tool_frame_fields() {
  static const ParamFields<ToolFrameParams> fields = {
      {{"pivot_depth_m", "m", 0.0, -0.01, 0.05,
        "depth of the robot's rotation centre below the skin apex, along the sensor axis (0 = the apex)"},
       &ToolFrameParams::pivot_depth_m},
      {{"press_offset_m", "m", 0.0, -0.002, 0.003,
        "how much deeper than recorded every press is, along the surface's normal (the robot's zero past the "
        "skin: > 0)"},
       &ToolFrameParams::press_offset_m},
  };
  return fields;
}

class ToolFrame final : public TypedEffect<ToolFrameParams> {
 public:
  // Ranges: the pivot from 10 mm above the apex to 50 mm below it (a dome's centre of curvature, 20 mm on the
  // TacTip, with margin for a flange-side tool point); the zero from 2 mm short of the skin to 3 mm past it (a
  // soft skin found by pressing it gives a zero past the skin; 3 mm is most of the TacTip's 1-5 mm presses).
  ToolFrame() : TypedEffect(tool_frame_fields()) {}

  std::string id() const override { return "tool_frame"; }
  std::string physics() const override {
    return "The recorded poses rotate the indenter about the skin's apex and count its depth from the skin. The "
           "robot rotated it about a point h below the apex on the sensor axis, c = (0, 0, -h): a rotation R about "
           "c moves every point by (I - R) c more than about the apex, p_EI + h (R z - z), R z the indenter's "
           "approach axis (its +z, E's +z untilted). And its zero lies d0 past the skin: every press is d0 deeper, "
           "p_EI - d0 R z. A flat surface at depth d and tilt t then penetrates a dome of radius r by "
           "d + d0 + (r - h)(1 - cos t) instead of d + r (1 - cos t): with h = r the depth no longer grows with the "
           "tilt. Twists about the sensor axis are unchanged.";
  }
  bool acts_on_pose() const override { return true; }
  bool needs_tilt() const override { return true; }

  Pose corrected_pose(const Pose& X_EI) const override {
    const double h = v().pivot_depth_m, d0 = v().press_offset_m;
    if (h == 0.0 && d0 == 0.0) return X_EI;
    Pose X = X_EI;
    const Vec3 z_E = Vec3::UnitZ();
    const Vec3 approach_E = X_EI.linear() * z_E;
    X.translation() += h * (approach_E - z_E) - d0 * approach_E;
    return X;
  }

  void apply(const EffectContext& /*ctx*/, std::vector<Vec2>& /*disp_px*/) override {}
  std::unique_ptr<Effect> clone() const override { return std::make_unique<ToolFrame>(*this); }
};

}  // namespace
std::unique_ptr<Effect> make_tool_frame() { return std::make_unique<ToolFrame>(); }
}  // namespace sb::effects
