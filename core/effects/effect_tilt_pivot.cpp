// tilt_pivot: the robot tilts the sensor about a point below the skin's apex, not about the apex that the
// recorded poses assume. A pose effect: it corrects the indenter's pose before the base model sees it.
#include "core/effects/effect_catalogue.hpp"

namespace sb::effects {
namespace {

struct TiltPivotParams {
  double pivot_depth_m = 0;
};

const ParamFields<TiltPivotParams>& tilt_pivot_fields() {
  static const ParamFields<TiltPivotParams> fields = {
      {{"pivot_depth_m", "m", 0.0, -0.01, 0.05,
        "depth of the robot's rotation centre below the skin apex, along the sensor axis (0 = the apex)"},
       &TiltPivotParams::pivot_depth_m},
  };
  return fields;
}

class TiltPivot final : public TypedEffect<TiltPivotParams> {
 public:
  // Range: from 10 mm above the apex to 50 mm below it (a dome's centre of curvature, 20 mm on the TacTip,
  // is the largest pivot a sensor-mounted tool frame plausibly has, with margin for a flange-mounted one).
  TiltPivot() : TypedEffect(tilt_pivot_fields()) {}

  std::string id() const override { return "tilt_pivot"; }
  std::string physics() const override {
    return "The recorded poses rotate the indenter about the skin's apex; the robot rotated it about a point h "
           "below the apex on the sensor axis, c = (0, 0, -h). A rotation R about c moves every point by "
           "(I - R) c more than about the apex, so the indenter's position becomes p_EI + h (R z - z), with R z "
           "the indenter's approach axis (its +z, which is E's +z untilted). A flat surface at depth d and tilt t "
           "then penetrates a dome of radius r by d + (r - h)(1 - cos t) instead of d + r (1 - cos t): with h = r "
           "the depth no longer grows with the tilt. Twists about the sensor axis are unchanged.";
  }
  bool acts_on_pose() const override { return true; }

  Pose corrected_pose(const Pose& X_EI) const override {
    const double h = v().pivot_depth_m;
    if (h == 0.0) return X_EI;
    Pose X = X_EI;
    const Vec3 z_E = Vec3::UnitZ();
    X.translation() += h * (X_EI.linear() * z_E - z_E);
    return X;
  }

  void apply(const EffectContext& /*ctx*/, std::vector<Vec2>& /*disp_px*/) override {}
  std::unique_ptr<Effect> clone() const override { return std::make_unique<TiltPivot>(*this); }
};

}  // namespace
std::unique_ptr<Effect> make_tilt_pivot() { return std::make_unique<TiltPivot>(); }
}  // namespace sb::effects
