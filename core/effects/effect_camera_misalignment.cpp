// camera_misalignment: camera axes rotated against E and a mis-calibrated pixel scale.
#include <cmath>

#include "core/effects/effect_catalogue.hpp"

namespace sb::effects {
namespace {

class CameraMisalignment final : public Effect {
 public:
  CameraMisalignment()
      : Effect({{"rotation_rad", "rad", 0.0, -0.2, 0.2, "camera roll about its optical axis against E"},
                {"scale", "", 1.0, 0.8, 1.25, "true / assumed pixels per metre"}}) {}

  std::string id() const override { return "camera_misalignment"; }
  std::string physics() const override {
    return "The camera is rolled by theta about its optical axis relative to the gel frame, and its mm/px "
           "calibration is off by a factor 1/s: every displacement vector is rotated and scaled, d -> s R(theta) d "
           "(exact for the orthographic camera: the map is linear, so it acts on displacements directly).";
  }

  void apply(const EffectContext& /*ctx*/, std::vector<Vec2>& disp_px) override {
    const double theta = params_.get("rotation_rad"), s = params_.get("scale");
    if (theta == 0.0 && s == 1.0) return;
    const double c = std::cos(theta), sn = std::sin(theta);
    for (Vec2& d : disp_px) d = s * Vec2(c * d.x() - sn * d.y(), sn * d.x() + c * d.y());
  }
  std::unique_ptr<Effect> clone() const override { return std::make_unique<CameraMisalignment>(*this); }
};

}  // namespace
std::unique_ptr<Effect> make_camera_misalignment() { return std::make_unique<CameraMisalignment>(); }
}  // namespace sb::effects
