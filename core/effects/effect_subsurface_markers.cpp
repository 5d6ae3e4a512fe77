// subsurface_markers: markers printed below the gel surface see a smoothed, attenuated field.
#include <cmath>

#include "core/effects/effect_catalogue.hpp"
#include "core/sensor/depth_smoothing.hpp"

namespace sb::effects {
namespace {

struct SubsurfaceMarkersParams {
  double depth_m = 0, attenuation = 0;
};

const ParamFields<SubsurfaceMarkersParams>& subsurface_markers_fields() {
  static const ParamFields<SubsurfaceMarkersParams> fields = {
      {{"depth_m", "m", 0.0, 0.0, 0.005, "marker depth below the surface = Gaussian smoothing width"},
       &SubsurfaceMarkersParams::depth_m},
      {{"attenuation", "", 1.0, 0.0, 1.0,
        "amplitude factor of the field at the marker depth (a field at depth is not stronger)"},
       &SubsurfaceMarkersParams::attenuation},
  };
  return fields;
}

class SubsurfaceMarkers final : public TypedEffect<SubsurfaceMarkersParams> {
 public:
  SubsurfaceMarkers() : TypedEffect(subsurface_markers_fields()) {}

  std::string id() const override { return "subsurface_markers"; }
  std::string physics() const override {
    return "Markers at depth h below the surface: the surface traction field reaches them spread over a "
           "region of width ~h (Boussinesq/Cerruti kernels decay with sqrt(r^2 + h^2)) and weakened. Modelled "
           "as a normalised Gaussian smoothing over the marker positions p_EM with sigma = h, times a.";
  }

  void apply(const EffectContext& ctx, std::vector<Vec2>& disp_px) override {
    const double h = v().depth_m, a = v().attenuation;
    if (h == 0.0) {  // no smoothing; a uniform attenuation (exactly the identity at a = 1)
      for (Vec2& d : disp_px) d *= a;
      return;
    }
    require_marker_count(ctx, disp_px, "subsurface_markers");
    update_weights(ctx.sensor->p_EM, h);
    disp_px = depth_smoothed(weights_, disp_px);
    for (Vec2& d : disp_px) d *= a;
  }
  std::unique_ptr<Effect> clone() const override { return std::make_unique<SubsurfaceMarkers>(*this); }

 private:
  // The weights (core/sensor/depth_smoothing) are rebuilt only when the depth or the markers change (fits
  // change h, replays do not).
  void update_weights(const std::vector<Vec3>& p_EM, double h) {
    if (h == cached_depth_ && p_EM == cached_markers_) return;
    weights_ = depth_smoothing_weights(p_EM, h);
    cached_depth_ = h;
    cached_markers_ = p_EM;
  }

  DepthSmoothingWeights weights_;
  double cached_depth_ = -1.0;
  std::vector<Vec3> cached_markers_;
};

}  // namespace
std::unique_ptr<Effect> make_subsurface_markers() { return std::make_unique<SubsurfaceMarkers>(); }
}  // namespace sb::effects
