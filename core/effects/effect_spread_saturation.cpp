// spread_saturation: under a broad contact the skin's outward spread stops growing with depth.
#include <algorithm>
#include <cmath>
#include <vector>

#include "core/effects/effect_catalogue.hpp"
#include "core/models/model_common.hpp"

namespace sb::effects {
namespace {

constexpr double kUnitM = 0.001;  // depths and offsets in the sum are counted in millimetres

// The markers inside the indenter and their depths h_k > 0.
struct InsideMarkers {
  std::vector<int> index;
  std::vector<double> depth_m;
};

InsideMarkers markers_inside(const EffectContext& ctx) {
  const std::vector<double> h = marker_penetration(ctx);
  InsideMarkers in;
  for (int k = 0; k < static_cast<int>(h.size()); ++k) {
    if (h[k] <= 0) continue;
    in.index.push_back(k);
    in.depth_m.push_back(h[k]);
  }
  return in;
}

struct SpreadSaturationParams {
  double gain_px = 0, depth_scale_m = 0, width_m = 0;
};

const ParamFields<SpreadSaturationParams>& spread_saturation_fields() {
  static const ParamFields<SpreadSaturationParams> fields = {
      {{"gain_px", "px", 0.0, 0.0, 10.0,
        "pull per mm of lost depth per mm of offset, at the kernel's centre (0: none)"},
       &SpreadSaturationParams::gain_px},
      {{"depth_scale_m", "m", 0.002, 2e-4, 0.01, "depth h0 at which the spread saturates: h0 tanh(h/h0)"},
       &SpreadSaturationParams::depth_scale_m},
      {{"width_m", "m", 0.003, 5e-4, 0.015, "width sigma of the spread's Gaussian kernel"},
       &SpreadSaturationParams::width_m},
  };
  return fields;
}

class SpreadSaturation final : public TypedEffect<SpreadSaturationParams> {
 public:
  SpreadSaturation() : TypedEffect(spread_saturation_fields()) {}

  std::string id() const override { return "spread_saturation"; }
  std::string physics() const override {
    return "A model's dilation pushes each marker away from every marker inside the indenter in proportion to "
           "that marker's depth h. Under a broad contact the skin sticks to the surface and the gel beneath is "
           "nearly incompressible: the spread stops growing with depth. Each inside marker's share is "
           "replaced by its saturated depth h0 tanh(h/h0): u_j += g sum_k (h0 tanh(h_k/h0) - h_k) (m_j - m_k) "
           "exp(-|m_j - m_k|^2 / (2 sigma^2)), depths and offsets in mm.";
  }

  void apply(const EffectContext& ctx, std::vector<Vec2>& disp_px) override {
    const double gain = v().gain_px;
    if (gain == 0.0 || ctx.indenter == nullptr || ctx.indenter->sdf == nullptr) return;
    require_marker_count(ctx, disp_px, "spread_saturation");
    const InsideMarkers in = markers_inside(ctx);
    if (in.index.empty()) return;
    const double h0 = v().depth_scale_m;
    const double inv_two_sigma2 = 1.0 / (2.0 * std::pow(v().width_m, 2));
    const std::vector<Vec3>& p_EM = ctx.sensor->p_EM;
    const int nm = static_cast<int>(p_EM.size());
    std::vector<double> kernel(nm);
    for (std::size_t i = 0; i < in.index.size(); ++i) {
      const double h = in.depth_m[i];
      const double lost = (h0 * std::tanh(h / h0) - h) / kUnitM;  // <= 0: the depth the spread no longer sees
      const Vec2 m_k = p_EM[in.index[i]].head<2>();
      // The kernel's exponents first, then one vectorised exp over them (exp_in_place, as HydroShear's sums).
      for (int j = 0; j < nm; ++j)
        kernel[j] = std::max(-(p_EM[j].head<2>() - m_k).squaredNorm() * inv_two_sigma2, -700.0);
      exp_in_place(kernel.data(), nm);
      for (int j = 0; j < nm; ++j) disp_px[j] += gain * lost * kernel[j] * ((p_EM[j].head<2>() - m_k) / kUnitM);
    }
  }
  std::unique_ptr<Effect> clone() const override { return std::make_unique<SpreadSaturation>(*this); }
};

}  // namespace
std::unique_ptr<Effect> make_spread_saturation() { return std::make_unique<SpreadSaturation>(); }
}  // namespace sb::effects
