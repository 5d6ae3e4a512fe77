// gravity_preload: the indenter's weight (or a tilted sensor's gravity component) as a constant shear
// pre-load while in contact.
#include <cmath>

#include "core/effects/effect_catalogue.hpp"

namespace sb::effects {
namespace {

struct GravityPreloadParams {
  double gx_px = 0, gy_px = 0, width_m = 0;
};

const ParamFields<GravityPreloadParams>& gravity_preload_fields() {
  static const ParamFields<GravityPreloadParams> fields = {
      {{"gx_px", "px", 0.0, -20.0, 20.0, "pre-load shear at the contact centre, u"}, &GravityPreloadParams::gx_px},
      {{"gy_px", "px", 0.0, -20.0, 20.0, "pre-load shear at the contact centre, v"}, &GravityPreloadParams::gy_px},
      {{"width_m", "m", 0.003, 1e-4, 0.03, "Gaussian width of the pre-loaded region", true},
       &GravityPreloadParams::width_m},
  };
  return fields;
}

class GravityPreload final : public TypedEffect<GravityPreloadParams> {
 public:
  GravityPreload() : TypedEffect(gravity_preload_fields()) {}

  std::string id() const override { return "gravity_preload"; }
  std::string physics() const override {
    return "A constant tangential load while in contact (the weight of a hand-held or hanging indenter, or "
           "gravity along a tilted sensor) adds a fixed shear g around the contact: "
           "d += g exp(-|p_EM - c|^2 / (2 w^2)), c the contact centre; nothing out of contact.";
  }

  void apply(const EffectContext& ctx, std::vector<Vec2>& disp_px) override {
    const Vec2 g(v().gx_px, v().gy_px);
    if (!ctx.in_contact || g.isZero(0.0)) return;
    require_marker_count(ctx, disp_px, "gravity_preload");
    const double w = v().width_m;
    for (std::size_t i = 0; i < disp_px.size(); ++i) {
      const double r2 = (ctx.sensor->p_EM[i].head<2>() - ctx.contact_centre_E).squaredNorm();
      disp_px[i] += g * std::exp(-r2 / (2.0 * w * w));
    }
  }
  std::unique_ptr<Effect> clone() const override { return std::make_unique<GravityPreload>(*this); }
};

}  // namespace
std::unique_ptr<Effect> make_gravity_preload() { return std::make_unique<GravityPreload>(); }
}  // namespace sb::effects
