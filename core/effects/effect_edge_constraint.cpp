// edge_constraint: a finite gel bonded/clamped at its walls moves less near the edges.
#include <algorithm>
#include <cmath>

#include "core/effects/effect_catalogue.hpp"

namespace sb::effects {
namespace {

struct EdgeConstraintParams {
  double length_m = 0, strength = 0;
};

const ParamFields<EdgeConstraintParams>& edge_constraint_fields() {
  static const ParamFields<EdgeConstraintParams> fields = {
      {{"length_m", "m", 0.002, 1e-4, 0.02, "decay length of the wall restraint", true},
       &EdgeConstraintParams::length_m},
      {{"strength", "", 0.0, 0.0, 1.0, "1: displacement pinned to zero at the wall; 0: free"},
       &EdgeConstraintParams::strength},
  };
  return fields;
}

class EdgeConstraint final : public TypedEffect<EdgeConstraintParams> {
 public:
  EdgeConstraint() : TypedEffect(edge_constraint_fields()) {}

  std::string id() const override { return "edge_constraint"; }
  std::string physics() const override {
    return "The gel pad is held by its frame: tangential displacement vanishes at a clamped wall and recovers "
           "over a boundary-layer length l (of the order of the gel thickness). Each marker's displacement "
           "is multiplied by 1 - s exp(-dist_to_edge / l), dist measured to the nearest side of the pad.";
  }

  void apply(const EffectContext& ctx, std::vector<Vec2>& disp_px) override {
    const double s = v().strength;
    if (s == 0.0) return;
    require_marker_count(ctx, disp_px, "edge_constraint");
    const double l = v().length_m;
    const Vec2 half = 0.5 * ctx.sensor->gel.size_m;
    for (std::size_t i = 0; i < disp_px.size(); ++i) {
      const Vec3& p = ctx.sensor->p_EM[i];
      const double dist = std::max(0.0, std::min(half.x() - std::abs(p.x()), half.y() - std::abs(p.y())));
      disp_px[i] *= 1.0 - s * std::exp(-dist / l);
    }
  }
  std::unique_ptr<Effect> clone() const override { return std::make_unique<EdgeConstraint>(*this); }
};

}  // namespace
std::unique_ptr<Effect> make_edge_constraint() { return std::make_unique<EdgeConstraint>(); }
}  // namespace sb::effects
