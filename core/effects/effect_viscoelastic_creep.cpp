// viscoelastic_creep: a standard linear solid (Zener) gel. See docs/effects.md.
#include <cmath>

#include "core/effects/effect_catalogue.hpp"

namespace sb::effects {
namespace {

struct ViscoelasticCreepParams {
  double tau_s = 0, creep_fraction = 0;
};

const ParamFields<ViscoelasticCreepParams>& viscoelastic_creep_fields() {
  static const ParamFields<ViscoelasticCreepParams> fields = {
      {{"tau_s", "s", 1.0, 1e-2, 10.0, "creep / recovery time constant", true}, &ViscoelasticCreepParams::tau_s},
      {{"creep_fraction", "", 0.0, -0.5, 1.0, "relaxed / instantaneous displacement - 1 (0: elastic gel, no creep)"},
       &ViscoelasticCreepParams::creep_fraction},
  };
  return fields;
}

class ViscoelasticCreep final : public TypedEffect<ViscoelasticCreepParams> {
 public:
  ViscoelasticCreep() : TypedEffect(viscoelastic_creep_fields()) {}

  std::string id() const override { return "viscoelastic_creep"; }
  std::string physics() const override {
    return "Standard linear solid: under a held load the field creeps from its instantaneous (glassy) value d "
           "toward the relaxed value (1 + c) d with time constant tau; after release the residual decays "
           "with the same tau. Per marker x' = (c d - x) / tau, output d + x (exact exp(-dt/tau) step).";
  }
  bool stateful() const override { return true; }
  void reset() override {
    creep_.clear();
    previous_input_.clear();
  }

  void apply(const EffectContext& ctx, std::vector<Vec2>& disp_px) override {
    if (creep_.size() != disp_px.size()) {  // first step (or a new marker set): an unloaded history
      creep_.assign(disp_px.size(), Vec2::Zero());
      previous_input_.assign(disp_px.size(), Vec2::Zero());
    }
    const double c = v().creep_fraction;
    // The load applied over (t - dt, t] is the previous step's base field, held (zero-order hold), so a
    // newly applied load shows its instantaneous value first and creeps afterwards.
    const double decay = std::exp(-ctx.dt_s / v().tau_s);
    for (std::size_t i = 0; i < disp_px.size(); ++i) {
      const Vec2 target = c * previous_input_[i];
      creep_[i] = target + (creep_[i] - target) * decay;
      previous_input_[i] = disp_px[i];
      disp_px[i] += creep_[i];
    }
  }
  std::unique_ptr<Effect> clone() const override { return std::make_unique<ViscoelasticCreep>(*this); }

 private:
  std::vector<Vec2> creep_;           // x: the delayed part of the field, per marker
  std::vector<Vec2> previous_input_;  // d at the previous step
};

}  // namespace
std::unique_ptr<Effect> make_viscoelastic_creep() { return std::make_unique<ViscoelasticCreep>(); }
}  // namespace sb::effects
