// load_stiffening: the gel's response per unit of the linear prediction falls with indentation depth.
#include <algorithm>

#include "core/effects/effect_catalogue.hpp"

namespace sb::effects {
namespace {

// The scale 1 / (1 + beta depth) is kept finite for softening (beta < 0) by flooring the denominator.
constexpr double kMinStiffeningDenominator = 0.1;

struct LoadStiffeningParams {
  double beta_per_m = 0;
};

const ParamFields<LoadStiffeningParams>& load_stiffening_fields() {
  static const ParamFields<LoadStiffeningParams> fields = {
      {{"beta_per_m", "1/m", 0.0, -200.0, 2000.0, "stiffening per metre of indentation (> 0 stiffens, < 0 softens)"},
       &LoadStiffeningParams::beta_per_m},
  };
  return fields;
}

class LoadStiffening final : public TypedEffect<LoadStiffeningParams> {
 public:
  LoadStiffening() : TypedEffect(load_stiffening_fields()) {}

  std::string id() const override { return "load_stiffening"; }
  std::string physics() const override {
    return "Linear models scale the field with indentation; a real gel stiffens: its neo-Hookean strain "
           "stiffening and the rigid backing under a thin (4.5 mm) layer raise the effective modulus roughly "
           "linearly with depth delta (finite-thickness Hertz correction ~ 1 + c a/h). The field is scaled by "
           "1 / (1 + beta delta), delta the indenter penetration.";
  }

  void apply(const EffectContext& ctx, std::vector<Vec2>& disp_px) override {
    const double beta = v().beta_per_m;
    if (beta == 0.0) return;
    const double scale = 1.0 / std::max(kMinStiffeningDenominator, 1.0 + beta * ctx.depth_m);
    for (Vec2& d : disp_px) d *= scale;
  }
  std::unique_ptr<Effect> clone() const override { return std::make_unique<LoadStiffening>(*this); }
};

}  // namespace
std::unique_ptr<Effect> make_load_stiffening() { return std::make_unique<LoadStiffening>(); }
}  // namespace sb::effects
