// dome_sway: a lateral load on a soft dome bends the whole tip: every pin moves with it, most at the apex.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include "core/effects/effect_catalogue.hpp"

namespace sb::effects {
namespace {

constexpr double kReferenceDepthM = 0.001;  // the load's unit: the normal load at 1 mm of penetration

// The unit normal of the gel's surface nearest to p_E: p_E moved onto the zero level set along the normal there
// (one step: exact for the analytic sphere and pad, close for a grid SDF).
Vec3 surface_normal_near(const Sdf& gel_sdf_E, const Vec3& p_E) {
  const Vec3 n = gel_normal_at(gel_sdf_E, p_E);
  return gel_normal_at(gel_sdf_E, p_E - gel_sdf_E.value(p_E) * n);
}

// Polar angle from the apex (about +z_E) at which the skin is clamped: a spherical cap's footprint rim; a flat or
// mesh gel is treated as clamped at 90 degrees (on a flat gel every pin has polar angle 0: a uniform shift).
double rim_polar_rad(const GelSpec& gel) {
  if (gel.surface == "spherical_cap" && gel.radius_m > 0)
    return std::asin(std::min(1.0, gel.footprint_radius_m / gel.radius_m));
  return 0.5 * std::numbers::pi;
}

struct DomeSwayParams {
  double compliance_m = 0, friction = 0, load_exponent = 0, stick_travel_m = 0, rotation_rad = 0, centre_depth_m = 0,
         torsion_rad = 0;
};

const ParamFields<DomeSwayParams>& dome_sway_fields() {
  static const ParamFields<DomeSwayParams> fields = {
      {{"compliance_m", "m", 0.0, 0.0, 0.002,
        "apex pin's lateral shift per unit lateral load (the load at 1 mm depth, along the slide or the tilt)"},
       &DomeSwayParams::compliance_m},
      {{"friction", "", 1.0, 0.0, 3.0, "sliding friction: the lateral load per unit normal load along the slide"},
       &DomeSwayParams::friction},
      {{"load_exponent", "", 2.0, 0.5, 3.0, "normal load ~ depth^q (hydroelastic pressure on a dome: 2; Hertz: 1.5)"},
       &DomeSwayParams::load_exponent},
      {{"stick_travel_m", "m", 3e-4, 1e-5, 3e-3, "slide in contact after which the skin fully slips"},
       &DomeSwayParams::stick_travel_m},
      {{"rotation_rad", "rad", 0.0, 0.0, 0.005,
        "the tip's turn per unit lateral load, towards the load (a bent post's top tilts as it deflects)"},
       &DomeSwayParams::rotation_rad},
      {{"centre_depth_m", "m", 0.02, 0.0, 0.05,
        "depth below the apex of the point on the axis the tip turns about (the rim's clamp of a hemisphere: its "
        "radius)"},
       &DomeSwayParams::centre_depth_m},
      {{"torsion_rad", "rad", 0.0, 0.0, 0.002,
        "the tip's twist about its axis per unit torque (unit load x 1 mm): friction at a contact off the axis, or "
        "a twisting contact, winds the dome up"},
       &DomeSwayParams::torsion_rad},
  };
  return fields;
}

class DomeSway final : public TypedEffect<DomeSwayParams> {
 public:
  // Ranges: the apex shift per unit load from none to 2 mm (the whole 4-5 mm deep TacTip press moves the field by
  // ~1 mm); an effective sliding friction up to 3 (silicone on a rough plate); the load's growth with depth
  // between a line contact's (1/2) and three times a cylinder's (1); the stick length from 10 um to 3 mm; the
  // turn per unit load from none to 5 mrad (0.3 deg: at the TacTip's deepest presses, load ~ 50, 14 deg); its
  // centre from the apex down to 2.5 dome radii (the tip's body below the skin's clamp); the twist per unit torque
  // from none to 2 mrad (the TacTip's deepest tilted slides, torque ~ 25 x 10 mm, 0.5 rad at most).
  DomeSway() : TypedEffect(dome_sway_fields()) {}

  std::string id() const override { return "dome_sway"; }
  std::string physics() const override {
    return "A soft dome clamped at its rim bends as a whole under a lateral load, so every pin shifts with the "
           "tip, most at the apex and none at the clamp: u(pin) = w(theta) c (delta / 1 mm)^q (mu s - n_xy), "
           "w = cos(pi/2 theta / theta_rim), theta the pin's polar angle. The normal load ~ delta^q pushes along the "
           "skin's normal at the contact (its lateral part -n_xy: a tilted flat on a dome); sliding friction adds "
           "mu times it along the slide s (|s| <= 1: the travel in contact over the stick length, clipped as the "
           "contact slips). The tip also turns towards the load about a point on its axis at depth z_c below the "
           "apex: every pin tip p goes to c + Rot(omega)(p - c), omega = r (delta / 1 mm)^q z x (mu s - n_xy) (a bent "
           "post's top tilts as it deflects; with the rim clamped, the turn rocks the whole skin). The friction's "
           "torque about the axis twists the dome: tau = (delta / 1 mm)^q mu ((p_c x s)_z + rho s_psi) / 1 mm, p_c "
           "the contact's centre, rho = 2a/3 the mean lever of a flat's contact on the cap (a = sqrt(2 R delta)), "
           "s_psi the indenter's turn in contact times rho over the stick length (clipped like s); each pin turns "
           "about the axis by w(theta) k tau. Kernel models of a half-space (HydroShear, FOTS, TacSL) have no such "
           "global mode.";
  }
  bool observes_steps() const override { return true; }
  void reset() override {
    travel_E_ = Vec2::Zero();
    last_xy_E_.reset();
    turn_rad_ = 0.0;
    last_yaw_.reset();
  }

  // The slide s: the indenter's travel in contact, the anchor dragged along once it exceeds the stick length.
  void observe_step(const Pose& X_EI, const Penetration& penetration) override {
    const Vec2 xy = X_EI.translation().head<2>();
    if (!penetration.penetrating) {
      reset();
      return;
    }
    if (last_xy_E_) travel_E_ += xy - *last_xy_E_;
    last_xy_E_ = xy;
    const double t0 = v().stick_travel_m;
    if (travel_E_.norm() > t0) travel_E_ *= t0 / travel_E_.norm();
    // The indenter's turn about z_E in contact (apply clips its arc at the contact's mean lever at t0).
    const Mat3 R = X_EI.linear();
    const double yaw = std::atan2(R(1, 0), R(0, 0));
    if (last_yaw_) turn_rad_ += std::remainder(yaw - *last_yaw_, 2.0 * std::numbers::pi);
    last_yaw_ = yaw;
  }

  void apply(const EffectContext& ctx, std::vector<Vec2>& disp_px) override {
    const double c = v().compliance_m;
    if ((c == 0.0 && v().rotation_rad == 0.0 && v().torsion_rad == 0.0) || !ctx.in_contact || ctx.depth_m <= 0.0)
      return;
    require_marker_count(ctx, disp_px, "dome_sway");
    const Sensor& s = *ctx.sensor;
    const Vec3 n_contact = surface_normal_near(*s.gel_sdf, Vec3(ctx.contact_centre_E.x(), ctx.contact_centre_E.y(), 0));
    const Vec2 slide = travel_E_ / v().stick_travel_m;
    const double normal_load = std::pow(ctx.depth_m / kReferenceDepthM, v().load_exponent);
    const Vec2 load = normal_load * (v().friction * slide - n_contact.head<2>());
    const Vec3 u_apex(c * load.x(), c * load.y(), 0.0);
    const Eigen::AngleAxisd turn = turn_towards(load);
    const double twist = v().torsion_rad * normal_load * v().friction * torque_lever(ctx, slide, s.gel);
    const Vec3 centre_E(0.0, 0.0, -v().centre_depth_m);
    cache_pins(s);
    for (std::size_t j = 0; j < disp_px.size(); ++j) {
      const Vec3 turned_E = centre_E + turn * (tips_E_[j] - centre_E);
      const Vec3 twisted_E = Eigen::AngleAxisd(weights_[j] * twist, Vec3::UnitZ()) * turned_E;
      disp_px[j] += s.camera.project(twisted_E + weights_[j] * u_apex) - s.camera.project(tips_E_[j]);
    }
  }
  std::unique_ptr<Effect> clone() const override { return std::make_unique<DomeSway>(*this); }

 private:
  // omega = r z x load: about the horizontal axis across the load, by r |load| (the identity without a load).
  Eigen::AngleAxisd turn_towards(const Vec2& load) const {
    const Vec3 omega = v().rotation_rad * Vec3(-load.y(), load.x(), 0.0);
    const double angle = omega.norm();
    return angle > 0.0 ? Eigen::AngleAxisd(angle, omega / angle) : Eigen::AngleAxisd(0.0, Vec3::UnitZ());
  }

  // (p_c x s)_z + rho s_psi in mm: the friction's lever about the axis per unit friction load. The twist's lever
  // rho = 2a/3 (a flat's contact on a cap of radius R: a = sqrt(2 R delta), uniform pressure); none on other gels.
  double torque_lever(const EffectContext& ctx, const Vec2& slide, const GelSpec& gel) const {
    const double off_axis = ctx.contact_centre_E.x() * slide.y() - ctx.contact_centre_E.y() * slide.x();
    double twisting = 0.0;
    if (gel.surface == "spherical_cap" && gel.radius_m > 0 && turn_rad_ != 0.0) {
      const double rho = 2.0 / 3.0 * std::sqrt(2.0 * gel.radius_m * ctx.depth_m);
      twisting = std::clamp(rho * turn_rad_ / v().stick_travel_m, -1.0, 1.0) * rho;
    }
    return (off_axis + twisting) / kReferenceDepthM;
  }

  // The pins' tips and profile weights depend on the sensor alone: computed once per sensor, not per field (a
  // fit applies the effect at every scored frame of every sample, hundreds of times).
  void cache_pins(const Sensor& s) {
    if (cached_for_ == &s && tips_E_.size() == s.p_EM.size()) return;
    const double rim = rim_polar_rad(s.gel);
    tips_E_.clear();
    weights_.clear();
    for (const Vec3& p_EM : s.p_EM) {
      const Vec3 n_rest = surface_normal_near(*s.gel_sdf, p_EM);
      const double theta = std::acos(std::clamp(n_rest.z(), -1.0, 1.0));
      weights_.push_back(std::cos(0.5 * std::numbers::pi * std::min(1.0, theta / rim)));
      tips_E_.push_back(p_EM - s.gel.markers_depth_m * n_rest);
    }
    cached_for_ = &s;
  }

  const Sensor* cached_for_ = nullptr;  // only compared, never read: the sensor the cache was computed for
  std::vector<Vec3> tips_E_;            // pin tips, L below the surface along the rest normal
  std::vector<double> weights_;         // cos(pi/2 theta / theta_rim)
  Vec2 travel_E_ = Vec2::Zero();        // the slide in contact, |travel| <= stick length
  std::optional<Vec2> last_xy_E_;       // the indenter's xy at the last step in contact
  double turn_rad_ = 0.0;               // the indenter's turn about z_E in contact
  std::optional<double> last_yaw_;      // the indenter's yaw about z_E at the last step in contact
};

}  // namespace
std::unique_ptr<Effect> make_dome_sway() { return std::make_unique<DomeSway>(); }
}  // namespace sb::effects
