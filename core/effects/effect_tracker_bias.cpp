// tracker_bias: systematic error of the marker tracker.
#include "core/effects/effect_catalogue.hpp"

namespace sb::effects {
namespace {

class TrackerBias final : public Effect {
 public:
  TrackerBias()
      : Effect({{"gain", "", 1.0, 0.5, 1.5, "tracked / true displacement"},
                {"bias_x_px", "px", 0.0, -5.0, 5.0, "constant offset on moving markers, u"},
                {"bias_y_px", "px", 0.0, -5.0, 5.0, "constant offset on moving markers, v"},
                {"moving_threshold_px", "px", 0.5, 0.0, 10.0, "a marker moves when |d| exceeds this"}}) {}

  std::string id() const override { return "tracker_bias"; }
  std::string physics() const override {
    return "Blob trackers err systematically: centroids of blurred or partly occluded dots under-/over-report "
           "motion (gain g), and a dragged dot deforms and is shaded by the indenter, which shifts its centroid "
           "by a roughly constant offset b. Output g d + b on markers with |d| > threshold, g d elsewhere.";
  }

  void apply(const EffectContext& /*ctx*/, std::vector<Vec2>& disp_px) override {
    const double g = params_.get("gain");
    const Vec2 b(params_.get("bias_x_px"), params_.get("bias_y_px"));
    const double threshold = params_.get("moving_threshold_px");
    for (Vec2& d : disp_px) {
      const bool moving = d.norm() > threshold;
      d *= g;
      if (moving) d += b;
    }
  }
  std::unique_ptr<Effect> clone() const override { return std::make_unique<TrackerBias>(*this); }
};

}  // namespace
std::unique_ptr<Effect> make_tracker_bias() { return std::make_unique<TrackerBias>(); }
}  // namespace sb::effects
