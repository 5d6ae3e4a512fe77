// tracker_bias: systematic error of the marker tracker.
#include "core/effects/effect_catalogue.hpp"

namespace sb::effects {
namespace {

struct TrackerBiasParams {
  double gain = 0, bias_x_px = 0, bias_y_px = 0, moving_threshold_px = 0;
};

const ParamFields<TrackerBiasParams>& tracker_bias_fields() {
  static const ParamFields<TrackerBiasParams> fields = {
      {{"gain", "", 1.0, 0.5, 1.5, "tracked / true displacement"}, &TrackerBiasParams::gain},
      {{"bias_x_px", "px", 0.0, -5.0, 5.0, "constant offset on moving markers, u"}, &TrackerBiasParams::bias_x_px},
      {{"bias_y_px", "px", 0.0, -5.0, 5.0, "constant offset on moving markers, v"}, &TrackerBiasParams::bias_y_px},
      {{"moving_threshold_px", "px", 0.5, 0.0, 10.0, "a marker moves when |d| exceeds this"},
       &TrackerBiasParams::moving_threshold_px},
  };
  return fields;
}

class TrackerBias final : public TypedEffect<TrackerBiasParams> {
 public:
  TrackerBias() : TypedEffect(tracker_bias_fields()) {}

  std::string id() const override { return "tracker_bias"; }
  std::string physics() const override {
    return "Blob trackers err systematically: centroids of blurred or partly occluded dots under-/over-report "
           "motion (gain g), and a dragged dot deforms and is shaded by the indenter, which shifts its centroid "
           "by a roughly constant offset b. Output g d + b on markers with |d| > threshold, g d elsewhere.";
  }

  void apply(const EffectContext& /*ctx*/, std::vector<Vec2>& disp_px) override {
    const double g = v().gain;
    const Vec2 b(v().bias_x_px, v().bias_y_px);
    const double threshold = v().moving_threshold_px;
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
