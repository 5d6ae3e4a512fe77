// pin_lever: pins standing on the inside of the skin turn with it (large deformation of a TacTip-like skin).
#include "core/effects/effect_catalogue.hpp"

namespace sb::effects {
namespace {

struct PinLeverParams {
  double gain = 0;
};

const ParamFields<PinLeverParams>& pin_lever_fields() {
  static const ParamFields<PinLeverParams> fields = {
      {{"gain", "", 0.0, 0.0, 2.0,
        "fraction of the skin's rotation its pins follow (1 = rigid pins along the surface normal)"},
       &PinLeverParams::gain},
  };
  return fields;
}

class PinLever final : public TypedEffect<PinLeverParams> {
 public:
  // Range: from pins that keep their direction (0) to twice the rigid lever (a pin longer than the depth the
  // camera sees it at, or a skin that turns more than its contact face).
  PinLever() : TypedEffect(pin_lever_fields()) {}

  std::string id() const override { return "pin_lever"; }
  std::string physics() const override {
    return "Pins hang from the skin along its inward normal, their tips a length L (the pins' depth) below the "
           "contact surface. Where the skin takes the indenter's shape its normal turns from n_rest to n_new (the "
           "indenter's face), and a pin that follows with gain g moves its tip by -g L (n_new - n_rest) on top of "
           "the skin's own displacement: outward by g L sin(phi) under a flat pressed on a dome, phi the pin's "
           "angle from the contact's centre. Imaged: project(tip + delta) - project(tip).";
  }
  bool acts_on(const Sensor& sensor) const override { return sensor.gel.markers_depth_m > 0; }

  void apply(const EffectContext& ctx, std::vector<Vec2>& disp_px) override {
    const double g = v().gain;
    if (g == 0.0 || !ctx.in_contact) return;
    require_marker_count(ctx, disp_px, "pin_lever");
    const Sensor& s = *ctx.sensor;
    const double L = s.gel.markers_depth_m;
    if (L <= 0 || ctx.indenter == nullptr) return;
    const Pose X_IE = ctx.X_EI.inverse();
    const Mat3 R_EI = ctx.X_EI.linear();
    for (std::size_t j = 0; j < disp_px.size(); ++j) {
      const Vec3& p_EM = s.p_EM[j];
      Vec3 grad_I;
      if (ctx.indenter->sdf->value_and_gradient(X_IE * p_EM, &grad_I) >= 0.0 || grad_I.squaredNorm() == 0.0) continue;
      const Vec3 n_rest = gel_normal_at(*s.gel_sdf, p_EM);
      if (n_rest.squaredNorm() == 0.0) continue;
      const Vec3 n_new = -(R_EI * grad_I).normalized();  // the skin faces the indenter's face
      const Vec3 tip = p_EM - L * n_rest;
      disp_px[j] += s.camera.project(tip - g * L * (n_new - n_rest)) - s.camera.project(tip);
    }
  }
  std::unique_ptr<Effect> clone() const override { return std::make_unique<PinLever>(*this); }
};

}  // namespace
std::unique_ptr<Effect> make_pin_lever() { return std::make_unique<PinLever>(); }
}  // namespace sb::effects
