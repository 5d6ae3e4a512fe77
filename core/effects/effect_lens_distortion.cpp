// lens_distortion: radial (Brown-Conrady k1, k2) distortion about the principal point.
#include <cmath>

#include "core/effects/effect_catalogue.hpp"

namespace sb::effects {
namespace {

struct LensDistortionParams {
  double k1 = 0, k2 = 0;
};

const ParamFields<LensDistortionParams>& lens_distortion_fields() {
  static const ParamFields<LensDistortionParams> fields = {
      {{"k1", "", 0.0, -1.0, 1.0, "radial distortion, r^2 term (r / image half-diagonal)"}, &LensDistortionParams::k1},
      {{"k2", "", 0.0, -1.0, 1.0, "radial distortion, r^4 term"}, &LensDistortionParams::k2},
  };
  return fields;
}

class LensDistortion final : public TypedEffect<LensDistortionParams> {
 public:
  LensDistortion() : TypedEffect(lens_distortion_fields()) {}

  std::string id() const override { return "lens_distortion"; }
  std::string physics() const override {
    return "Radial lens distortion about the principal point c: a point at normalised radius r (pixels / image "
           "half-diagonal) is imaged at c + (p - c)(1 + k1 r^2 + k2 r^4); a marker's displacement becomes "
           "D(m + d) - D(m). Barrel: k1 < 0, pincushion: k1 > 0.";
  }

  void apply(const EffectContext& ctx, std::vector<Vec2>& disp_px) override {
    const double k1 = v().k1, k2 = v().k2;
    if (k1 == 0.0 && k2 == 0.0) return;  // exactly the identity (D(m + d) - D(m) would round)
    require_marker_count(ctx, disp_px, "lens_distortion");
    const Camera& cam = ctx.sensor->camera;
    const double half_diagonal = 0.5 * std::hypot(double(cam.width_px), double(cam.height_px));
    const auto distort = [&](const Vec2& p) {
      const Vec2 q = p - cam.principal_px;
      const double r2 = q.squaredNorm() / (half_diagonal * half_diagonal);
      return Vec2(cam.principal_px + q * (1.0 + k1 * r2 + k2 * r2 * r2));
    };
    for (std::size_t i = 0; i < disp_px.size(); ++i) {
      const Vec2& m = ctx.sensor->markers_rest_px[i];
      disp_px[i] = distort(m + disp_px[i]) - distort(m);
    }
  }
  std::unique_ptr<Effect> clone() const override { return std::make_unique<LensDistortion>(*this); }
};

}  // namespace
std::unique_ptr<Effect> make_lens_distortion() { return std::make_unique<LensDistortion>(); }
}  // namespace sb::effects
