// camera_misalignment: camera axes rotated against E and a mis-calibrated pixel scale.
#include <cmath>

#include "core/effects/effect_catalogue.hpp"

namespace sb::effects {
namespace {

struct CameraMisalignmentParams {
  double rotation_rad = 0, scale = 0;
};

const ParamFields<CameraMisalignmentParams>& camera_misalignment_fields() {
  static const ParamFields<CameraMisalignmentParams> fields = {
      {{"rotation_rad", "rad", 0.0, -0.2, 0.2, "camera roll about its optical axis against E"},
       &CameraMisalignmentParams::rotation_rad},
      {{"scale", "", 1.0, 0.8, 1.25, "true / assumed pixels per metre"}, &CameraMisalignmentParams::scale},
  };
  return fields;
}

class CameraMisalignment final : public TypedEffect<CameraMisalignmentParams> {
 public:
  CameraMisalignment() : TypedEffect(camera_misalignment_fields()) {}

  std::string id() const override { return "camera_misalignment"; }
  std::string physics() const override {
    return "The camera is rolled by theta about its optical axis relative to the gel frame, and its mm/px "
           "calibration is off by a factor 1/s: every displacement vector is rotated and scaled, d -> s R(theta) d "
           "(exact for the orthographic camera: the map is linear, so it acts on displacements directly).";
  }

  void apply(const EffectContext& /*ctx*/, std::vector<Vec2>& disp_px) override {
    const double theta = v().rotation_rad, s = v().scale;
    if (theta == 0.0 && s == 1.0) return;
    const double c = std::cos(theta), sn = std::sin(theta);
    for (Vec2& d : disp_px) d = s * Vec2(c * d.x() - sn * d.y(), sn * d.x() + c * d.y());
  }
  std::unique_ptr<Effect> clone() const override { return std::make_unique<CameraMisalignment>(*this); }
};

}  // namespace
std::unique_ptr<Effect> make_camera_misalignment() { return std::make_unique<CameraMisalignment>(); }
}  // namespace sb::effects
