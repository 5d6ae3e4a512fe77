// skin_indentation: the skin under a contact is pushed in along its normal, and a camera with perspective sees it.
#include <cmath>
#include <memory>
#include <vector>

#include "core/effects/effect_catalogue.hpp"
#include "core/effects/spreading_kernel.hpp"

namespace sb::effects {
namespace {

using Kernel = SpreadingKernel;

struct SkinIndentationParams {
  double gain = 0, spread_m = 0;
};

const ParamFields<SkinIndentationParams>& skin_indentation_fields() {
  static const ParamFields<SkinIndentationParams> fields = {
      {{"gain", "", 0.0, 0.0, 1.5,
        "inward normal displacement of a pin per unit penetration of the skin above it (1: the skin takes the "
        "indenter's shape and its pins follow)"},
       &SkinIndentationParams::gain},
      {{"spread_m", "m", 0.0, 0.0, 0.006,
        "width of the Gaussian over which the skin spreads the indentation to its neighbours (0: none)"},
       &SkinIndentationParams::spread_m},
  };
  return fields;
}

class SkinIndentation final : public TypedEffect<SkinIndentationParams> {
 public:
  // Ranges: from a skin that does not move inward (0) to one that goes in half as far again as the indenter's
  // penetration (a pin longer than the depth the camera sees it at); the spread from none to a third of the TacTip
  // dome's 20 mm radius (a skin bending stiffly over the soft gel beneath).
  SkinIndentation() : TypedEffect(skin_indentation_fields()) {}

  std::string id() const override { return "skin_indentation"; }
  std::string physics() const override {
    return "Where an indenter presses the skin, the skin takes the indenter's shape: the surface moves inward along "
           "its normal by the local penetration h, and the pins hanging from it follow. A kernel model's field is "
           "the surface's in-plane displacement only; an orthographic camera cannot see the normal part, a camera "
           "inside a dome can: a pin moving towards the dome's centre moves towards the principal point in the "
           "image. w = g (K h), K a row-normalised Gaussian of width spread over the pins (the identity at 0), "
           "d_px += project(tip - w n_rest) - project(tip), tip = p_EM - L n_rest.";
  }
  bool acts_on(const Sensor& sensor) const override { return sensor.camera.pinhole(); }

  void apply(const EffectContext& ctx, std::vector<Vec2>& disp_px) override {
    const double g = v().gain;
    if (g == 0.0 || !ctx.in_contact || ctx.indenter == nullptr || ctx.indenter->sdf == nullptr) return;
    require_marker_count(ctx, disp_px, "skin_indentation");
    const Sensor& s = *ctx.sensor;
    cache_pins(s);
    const std::vector<double> w = spread(marker_penetration(ctx));
    for (std::size_t j = 0; j < disp_px.size(); ++j) {
      if (w[j] == 0.0) continue;
      disp_px[j] += s.camera.project(tips_E_[j] - g * w[j] * normals_E_[j]) - s.camera.project(tips_E_[j]);
    }
  }
  std::unique_ptr<Effect> clone() const override { return std::make_unique<SkinIndentation>(*this); }

 private:
  // The pins' tips and rest normals depend on the sensor alone (a fit applies the effect at every scored frame of
  // every sample); the spreading kernel on the sensor and the width.
  void cache_pins(const Sensor& s) {
    if (cached_for_ != &s || tips_E_.size() != s.p_EM.size()) {
      tips_E_.clear();
      normals_E_.clear();
      for (const Vec3& p_EM : s.p_EM) {
        normals_E_.push_back(gel_normal_at(*s.gel_sdf, p_EM));
        tips_E_.push_back(p_EM - s.gel.markers_depth_m * normals_E_.back());
      }
      cached_for_ = &s;
      kernel_for_spread_m_ = -1.0;
    }
    if (kernel_for_spread_m_ != v().spread_m) build_kernel(s.p_EM);
  }

  // The shared spreading kernel at the current width (none at spread 0: no spreading).
  void build_kernel(const std::vector<Vec3>& p_EM) {
    const double sigma = v().spread_m;
    kernel_ = sigma > 0.0 ? shared_spreading_kernel(p_EM, sigma) : nullptr;
    kernel_for_spread_m_ = sigma;
  }

  std::vector<double> spread(const std::vector<double>& h) const {
    if (!kernel_) return h;
    const Kernel& kernel = *kernel_;
    const std::size_t n = h.size();
    std::vector<double> w(n, 0.0);
    for (std::size_t k = 0; k < n; ++k) {
      if (h[k] == 0.0) continue;  // most pins are outside the contact
      for (std::size_t j = 0; j < n; ++j) w[j] += kernel[j * n + k] * h[k];
    }
    return w;
  }

  const Sensor* cached_for_ = nullptr;    // only compared, never read: the sensor the cache was computed for
  std::vector<Vec3> tips_E_;              // pin tips, L below the surface along the rest normal
  std::vector<Vec3> normals_E_;           // the skin's outward rest normal at each pin
  std::shared_ptr<const Kernel> kernel_;  // n x n, row-major (shared_spreading_kernel); null without spreading
  double kernel_for_spread_m_ = -1.0;
};

}  // namespace
std::unique_ptr<Effect> make_skin_indentation() { return std::make_unique<SkinIndentation>(); }
}  // namespace sb::effects
