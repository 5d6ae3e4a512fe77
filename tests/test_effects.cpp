#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <numbers>

#include "core/effects/effects.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_effects {

using namespace sb;

namespace {

constexpr double kExact = 1e-12;     // px: closed-form arithmetic on O(1..100) px values
constexpr double kDepthTol = 1e-12;  // metres: analytic SDFs

constexpr double kSphereRadius = 0.004;
const Vec2 kGelSize(0.02, 0.016);
constexpr double kGelThickness = 0.0045;

// A sensor with markers at the given xy (metres, in E), seen by the default orthographic camera.
std::shared_ptr<Sensor> make_test_sensor(const std::vector<Vec2>& p_E_xy) {
  auto s = std::make_shared<Sensor>();
  s->gel.size_m = kGelSize;
  s->gel.thickness_m = kGelThickness;
  s->gel_sdf = make_pad_sdf(kGelSize, kGelThickness);
  for (const Vec2& p : p_E_xy) {
    s->p_EM.emplace_back(p.x(), p.y(), 0.0);
    s->markers_rest_px.push_back(s->camera.px_from_E(p));
  }
  return s;
}

std::shared_ptr<Sensor> make_grid_sensor() {
  std::vector<Vec2> p;
  for (int r = -1; r <= 1; ++r)
    for (int c = -1; c <= 1; ++c) p.emplace_back(0.003 * c, 0.003 * r);
  return make_test_sensor(p);
}

// A sphere whose samples are its bottom pole and a ring of four points 45 degrees below the equator,
// so the penetration of a pose is known in closed form.
std::shared_ptr<Indenter> make_test_indenter() {
  auto ind = std::make_shared<Indenter>();
  ind->name = "test-sphere";
  ind->sdf = make_sphere_sdf(kSphereRadius);
  const double r = kSphereRadius, q = kSphereRadius * std::sqrt(0.5);
  ind->samples.p_IS = {Vec3(0, 0, -r), Vec3(q, 0, -q), Vec3(-q, 0, -q), Vec3(0, q, -q), Vec3(0, -q, -q)};
  return ind;
}

// Sphere centre at (x, y) pressed `depth` into the flat pad (negative depth: above it).
Pose pressed(double depth, double x = 0.0, double y = 0.0) {
  Pose X = Pose::Identity();
  X.translation() = Vec3(x, y, kSphereRadius - depth);
  return X;
}

// The in-test base model: a fixed field, times `gain`, while the sphere touches the gel (centre z < R).
class FixedFieldModel final : public ShearModel {
 public:
  explicit FixedFieldModel(std::vector<Vec2> field)
      : field_(std::move(field)), params_({{"gain", "", 1.0, 0.0, 10.0, "field scale"}}) {}
  std::string id() const override { return "fixed"; }
  const ParamSet& params() const override { return params_; }
  void set_params(const ParamSet& p) override { params_ = p; }
  void reset() override {}
  void step(const Pose& X_EI, double, FieldOutput* out) override {
    if (out == nullptr) return;  // no field wanted (ShearModel::step's contract)
    const bool touching = X_EI.translation().z() < kSphereRadius;
    out->disp_px.assign(field_.size(), Vec2::Zero());
    out->marker_in_contact.assign(field_.size(), touching ? 1 : 0);
    if (touching)
      for (std::size_t i = 0; i < field_.size(); ++i) out->disp_px[i] = params_.get("gain") * field_[i];
  }
  std::unique_ptr<ShearModel> clone() const override { return std::make_unique<FixedFieldModel>(*this); }

 private:
  std::vector<Vec2> field_;
  ParamSet params_;
};

std::vector<Vec2> test_field(std::size_t n) {
  std::vector<Vec2> f;
  for (std::size_t i = 0; i < n; ++i) f.emplace_back(1.0 + 0.5 * double(i), -2.0 + 0.25 * double(i));
  return f;
}

// Approach, press, hold, slide, release: poses with 10 ms steps.
std::vector<Pose> test_trajectory() {
  std::vector<Pose> t;
  for (int k = 0; k <= 30; ++k) t.push_back(pressed(-0.001 + 0.0001 * k));        // to 2 mm deep
  for (int k = 0; k < 20; ++k) t.push_back(pressed(0.002, 0.0001 * k, 0.0));      // hold and slide
  for (int k = 0; k <= 30; ++k) t.push_back(pressed(0.002 - 0.0001 * k, 0.002));  // release
  return t;
}
constexpr double kDt = 0.01;

EffectContext context_for(const Sensor* sensor, double depth = 0.0, bool contact = false) {
  EffectContext ctx;
  ctx.sensor = sensor;
  ctx.dt_s = kDt;
  ctx.depth_m = depth;
  ctx.in_contact = contact;
  return ctx;
}

Vec2 apply_one(Effect& e, const EffectContext& ctx, const std::vector<Vec2>& field, std::size_t marker) {
  std::vector<Vec2> d = field;
  e.apply(ctx, d);
  return d[marker];
}

// Records what the wrapper passes to effects.
class RecordingEffect final : public Effect {
 public:
  RecordingEffect() : Effect({}) {}
  std::string id() const override { return "recorder"; }
  std::string physics() const override { return "records the context"; }
  void apply(const EffectContext& ctx, std::vector<Vec2>&) override { seen.push_back(ctx); }
  std::unique_ptr<Effect> clone() const override { return std::make_unique<RecordingEffect>(*this); }
  std::vector<EffectContext> seen;
};

}  // namespace

TEST_CASE("effect registry makes every listed effect with described parameters", "[effects]") {
  REQUIRE(effect_ids().size() >= 7);
  for (const auto& id : effect_ids()) {
    auto e = make_effect(id);
    CHECK(e->id() == id);
    CHECK(!e->physics().empty());
    for (std::size_t i = 0; i < e->params().size(); ++i) {
      const ParamSpec& s = e->params().specs()[i];
      CHECK(s.min <= s.default_value);
      CHECK(s.default_value <= s.max);
      CHECK(!s.help.empty());
    }
  }
  CHECK_THROWS_AS(make_effect("no_such_effect"), std::invalid_argument);
}

TEST_CASE("a model wrapped with any effect at its defaults equals the base model", "[effects]") {
  const auto sensor = make_grid_sensor();
  const auto indenter = make_test_indenter();
  std::vector<std::vector<std::string>> cases;
  for (const auto& id : effect_ids()) cases.push_back({id});
  cases.push_back(effect_ids());  // all at once
  for (const auto& ids : cases) {
    FixedFieldModel base(test_field(9));
    auto wrapped = wrap_with_effects(std::make_unique<FixedFieldModel>(test_field(9)), ids, sensor, indenter);
    for (const Pose& X : test_trajectory()) {
      FieldOutput a, b;
      base.step(X, kDt, &a);
      wrapped->step(X, kDt, &b);
      REQUIRE(a.disp_px.size() == b.disp_px.size());
      for (std::size_t i = 0; i < a.disp_px.size(); ++i) REQUIRE(a.disp_px[i] == b.disp_px[i]);  // bit-exact
    }
  }
}

TEST_CASE("EffectModel concatenates and routes parameter tables; clone is deep", "[effects]") {
  const auto sensor = make_grid_sensor();
  auto m = wrap_with_effects(std::make_unique<FixedFieldModel>(test_field(9)),
                             {"viscoelastic_creep", "load_stiffening"}, sensor, make_test_indenter());
  CHECK(m->id() == "fixed+viscoelastic_creep+load_stiffening");
  // 1 base + 2 creep + 1 stiffening parameters, base names unchanged, effect names prefixed.
  REQUIRE(m->params().size() == 4);
  CHECK(m->params().specs()[0].name == "gain");
  CHECK(m->params().index_of("viscoelastic_creep.tau_s") >= 0);
  CHECK(m->params().index_of("viscoelastic_creep.creep_fraction") >= 0);
  CHECK(m->params().index_of("load_stiffening.beta_per_m") >= 0);

  ParamSet p = m->params();
  p.set("gain", 2.0);
  p.set("viscoelastic_creep.tau_s", 0.5);
  p.set("load_stiffening.beta_per_m", 100.0);
  m->set_params(p);
  CHECK(m->base().params().get("gain") == 2.0);
  CHECK(m->effect(0).params().get("tau_s") == 0.5);
  CHECK(m->effect(1).params().get("beta_per_m") == 100.0);
  CHECK(m->params().get("load_stiffening.beta_per_m") == 100.0);

  // A table from another model is rejected and leaves this one unchanged.
  ParamSet foreign(
      {{"gain", "", 1, 0, 10, ""}, {"x.y", "", 0, 0, 1, ""}, {"a", "", 0, 0, 1, ""}, {"b", "", 0, 0, 1, ""}});
  CHECK_THROWS_AS(m->set_params(foreign), std::invalid_argument);
  CHECK(m->params().get("gain") == 2.0);

  // Clone: same output from the same state; its parameters are its own.
  for (int k = 0; k < 5; ++k) {
    FieldOutput o;
    m->step(pressed(0.001), kDt, &o);
  }
  auto c = m->clone();
  FieldOutput a, b;
  m->step(pressed(0.001), kDt, &a);
  c->step(pressed(0.001), kDt, &b);
  for (std::size_t i = 0; i < a.disp_px.size(); ++i) CHECK(a.disp_px[i] == b.disp_px[i]);
  ParamSet q = c->params();
  q.set("viscoelastic_creep.tau_s", 3.0);
  c->set_params(q);
  CHECK(m->params().get("viscoelastic_creep.tau_s") == 0.5);

  std::vector<std::unique_ptr<Effect>> twice;
  twice.push_back(make_effect("tracker_bias"));
  twice.push_back(make_effect("tracker_bias"));
  CHECK_THROWS_AS(
      EffectModel(std::make_unique<FixedFieldModel>(test_field(9)), std::move(twice), sensor, make_test_indenter()),
      std::invalid_argument);
}

TEST_CASE("indenter penetration is the deepest -phi_E and its weighted centre", "[effects]") {
  const auto sensor = make_grid_sensor();
  const auto ind = make_test_indenter();
  // Pole 1 mm deep; ring points at z = R - 1 mm - R sqrt(1/2) = 0.17 mm, outside: depth 1 mm at the pole.
  Penetration p = indenter_penetration(*sensor->gel_sdf, *ind, pressed(0.001, 0.002, -0.001));
  CHECK(p.penetrating);
  CHECK(std::abs(p.depth_m - 0.001) < kDepthTol);
  CHECK((p.centre_E - Vec2(0.002, -0.001)).norm() < kDepthTol);
  // 2 mm deep: the symmetric ring also penetrates (0.83 mm); the depth stays the pole's, the centre the axis.
  p = indenter_penetration(*sensor->gel_sdf, *ind, pressed(0.002, 0.001, 0.0));
  CHECK(std::abs(p.depth_m - 0.002) < kDepthTol);
  CHECK((p.centre_E - Vec2(0.001, 0.0)).norm() < kDepthTol);
  // Above the gel: no penetration, centre below the lowest point.
  p = indenter_penetration(*sensor->gel_sdf, *ind, pressed(-0.001, 0.003, 0.004));
  CHECK(!p.penetrating);
  CHECK(p.depth_m == 0.0);
  CHECK((p.centre_E - Vec2(0.003, 0.004)).norm() < kDepthTol);
}

TEST_CASE("EffectModel passes time, depth, contact and loading to effects", "[effects]") {
  std::vector<std::unique_ptr<Effect>> fx;
  fx.push_back(std::make_unique<RecordingEffect>());
  EffectModel m(std::make_unique<FixedFieldModel>(test_field(9)), std::move(fx), make_grid_sensor(),
                make_test_indenter());
  const std::vector<double> depths = {-0.001, 0.0005, 0.001, 0.001, 0.0004};
  for (double d : depths) {
    FieldOutput o;
    m.step(pressed(d), kDt, &o);
  }
  const auto& seen = dynamic_cast<const RecordingEffect&>(m.effect(0)).seen;
  REQUIRE(seen.size() == depths.size());
  CHECK(!seen[0].in_contact);
  CHECK(!seen[0].loading);
  CHECK(seen[1].in_contact);
  CHECK(seen[1].loading);   // 0 -> 0.5 mm
  CHECK(seen[2].loading);   // 0.5 -> 1 mm
  CHECK(!seen[3].loading);  // held
  CHECK(!seen[4].loading);  // unloading
  CHECK(std::abs(seen[2].depth_m - 0.001) < kDepthTol);
  CHECK(std::abs(seen[4].time_s - 5 * kDt) < kExact);
  CHECK(seen[4].dt_s == kDt);
  m.reset();
  FieldOutput o;
  m.step(pressed(0.001), kDt, &o);
  CHECK(std::abs(dynamic_cast<const RecordingEffect&>(m.effect(0)).seen.back().time_s - kDt) < kExact);
  CHECK_THROWS_AS(m.step(pressed(0.001), -kDt, &o), std::invalid_argument);
  CHECK_THROWS_AS(m.step(pressed(0.001), std::nan(""), &o), std::invalid_argument);
}

TEST_CASE("viscoelastic_creep: delayed creep under a held load and delayed recovery", "[effects]") {
  auto e = make_effect("viscoelastic_creep");
  const double tau = 0.1, c = 0.5;
  ParamSet p = e->params();
  p.set("tau_s", tau);
  p.set("creep_fraction", c);
  e->set_params(p);
  const EffectContext ctx = context_for(nullptr);  // dt = tau / 10
  const Vec2 d(2.0, -1.0);
  // Step load: the first loaded step shows the glassy value d (the load has not acted for any time yet).
  CHECK((apply_one(*e, ctx, {d}, 0) - d).norm() < kExact);
  // Held for 10 more steps = tau. With constant input, x' = (c d - x)/tau, x(0) = 0 gives
  // x(t) = c d (1 - e^{-t/tau}); the exact-exponential step reproduces it, so at t = tau the output is
  // d + x = d (1 + c (1 - e^{-1})).
  Vec2 out;
  for (int k = 0; k < 10; ++k) out = apply_one(*e, ctx, {d}, 0);
  CHECK((out - d * (1.0 + c * (1.0 - std::exp(-1.0)))).norm() < kExact);
  // Release: the base field drops to 0 but the load acted over the last interval, so the residual is
  // x_r = c d (1 - e^{-1.1}); afterwards (input 0) x decays by e^{-1} per tau.
  const Vec2 residual = apply_one(*e, ctx, {Vec2::Zero()}, 0);
  CHECK((residual - c * d * (1.0 - std::exp(-1.1))).norm() < kExact);
  for (int k = 0; k < 10; ++k) out = apply_one(*e, ctx, {Vec2::Zero()}, 0);
  CHECK((out - residual * std::exp(-1.0)).norm() < kExact);
  // reset() forgets the history.
  e->reset();
  CHECK((apply_one(*e, ctx, {d}, 0) - d).norm() < kExact);
}

TEST_CASE("lens_distortion: a marker at r = 0.5 moves by the distorted difference", "[effects]") {
  // Default camera 320 x 240: half-diagonal R = 0.5 hypot(320, 240) = 200 px. A marker 100 px right of
  // the principal point (r0 = 0.5) displaced 20 px outward (r1 = 0.6) is imaged at
  //   D(r) = R r (1 + k1 r^2 + k2 r^4):  with k1 = 0.2, k2 = 0.1
  //   D(0.6) - D(0.5) = 200 (0.6 * 1.08496 - 0.5 * 1.05625) = 200 * 0.122851 = 24.5702 px along u.
  auto sensor = make_test_sensor({Vec2::Zero()});
  sensor->markers_rest_px = {sensor->camera.principal_px + Vec2(100.0, 0.0)};
  auto e = make_effect("lens_distortion");
  ParamSet p = e->params();
  p.set("k1", 0.2);
  p.set("k2", 0.1);
  e->set_params(p);
  const Vec2 out = apply_one(*e, context_for(sensor.get()), {Vec2(20.0, 0.0)}, 0);
  CHECK(std::abs(out.x() - 24.5702) < 1e-9);
  CHECK(std::abs(out.y()) < kExact);
  // Wrong marker count is an error, not a crash.
  std::vector<Vec2> two(2, Vec2::Zero());
  CHECK_THROWS_AS(e->apply(context_for(sensor.get()), two), std::invalid_argument);
}

TEST_CASE("subsurface_markers: uniform fields are only attenuated; smoothing mixes neighbours", "[effects]") {
  const auto grid = make_grid_sensor();
  auto e = make_effect("subsurface_markers");
  ParamSet p = e->params();
  p.set("depth_m", 0.001);
  p.set("attenuation", 0.7);
  e->set_params(p);
  // Row-normalised weights reproduce a uniform field, so only the factor a = 0.7 remains.
  std::vector<Vec2> uniform(9, Vec2(3.0, -1.0));
  e->apply(context_for(grid.get()), uniform);
  for (const Vec2& d : uniform) CHECK((d - 0.7 * Vec2(3.0, -1.0)).norm() < kExact);
  // Two markers h apart, field (1, 0) on the first only: w = e^{-h^2 / (2 h^2)} = e^{-1/2};
  // out_0 = a / (1 + w), out_1 = a w / (1 + w).
  const auto pair = make_test_sensor({Vec2(0, 0), Vec2(0.001, 0)});
  std::vector<Vec2> f = {Vec2(1, 0), Vec2(0, 0)};
  e->apply(context_for(pair.get()), f);
  const double w = std::exp(-0.5);
  CHECK(std::abs(f[0].x() - 0.7 / (1 + w)) < kExact);
  CHECK(std::abs(f[1].x() - 0.7 * w / (1 + w)) < kExact);
}

TEST_CASE("gravity_preload: shear g at the contact centre, g e^{-1/2} at one width, none off contact", "[effects]") {
  const double w = 0.003;
  const auto sensor = make_test_sensor({Vec2(0.001, 0.0), Vec2(0.001, w)});
  auto e = make_effect("gravity_preload");
  ParamSet p = e->params();
  p.set("gx_px", 1.5);
  p.set("gy_px", -0.5);
  p.set("width_m", w);
  e->set_params(p);
  EffectContext ctx = context_for(sensor.get(), 0.001, true);
  ctx.contact_centre_E = Vec2(0.001, 0.0);
  std::vector<Vec2> f(2, Vec2(1.0, 1.0));
  e->apply(ctx, f);
  CHECK((f[0] - Vec2(2.5, 0.5)).norm() < kExact);
  CHECK((f[1] - (Vec2(1.0, 1.0) + std::exp(-0.5) * Vec2(1.5, -0.5))).norm() < kExact);
  std::vector<Vec2> g(2, Vec2(1.0, 1.0));
  e->apply(context_for(sensor.get(), 0.0, false), g);
  CHECK(g[0] == Vec2(1.0, 1.0));
}

TEST_CASE("edge_constraint: a marker one length from the wall is scaled by 1 - s/e", "[effects]") {
  const double l = 0.002, s = 0.6;
  // Gel 20 x 16 mm: half-widths 10 and 8 mm. Marker A at x = 10 - 2 mm: nearest wall l away.
  // Marker B at the centre: nearest walls (y) 8 mm = 4 l away.
  const auto sensor = make_test_sensor({Vec2(0.01 - l, 0.0), Vec2(0.0, 0.0)});
  auto e = make_effect("edge_constraint");
  ParamSet p = e->params();
  p.set("length_m", l);
  p.set("strength", s);
  e->set_params(p);
  std::vector<Vec2> f(2, Vec2(2.0, -4.0));
  e->apply(context_for(sensor.get()), f);
  CHECK((f[0] - (1 - s * std::exp(-1.0)) * Vec2(2.0, -4.0)).norm() < kExact);
  CHECK((f[1] - (1 - s * std::exp(-4.0)) * Vec2(2.0, -4.0)).norm() < kExact);
}

TEST_CASE("load_stiffening scales by 1 / (1 + beta depth), floored for softening", "[effects]") {
  auto e = make_effect("load_stiffening");
  ParamSet p = e->params();
  p.set("beta_per_m", 500.0);
  e->set_params(p);
  // 1 mm deep: 1 / (1 + 500 * 0.001) = 1 / 1.5.
  CHECK((apply_one(*e, context_for(nullptr, 0.001), {Vec2(3, 6)}, 0) - Vec2(2, 4)).norm() < kExact);
  // Softening: beta = -200 at 5 mm gives 1 + beta delta = 0; the floor 0.1 caps the gain at 10.
  p.set("beta_per_m", -200.0);
  e->set_params(p);
  CHECK((apply_one(*e, context_for(nullptr, 0.005), {Vec2(1, 0)}, 0) - Vec2(10, 0)).norm() < 1e-9);
}

TEST_CASE("tracker_bias: gain everywhere, bias only on moving markers", "[effects]") {
  auto e = make_effect("tracker_bias");
  ParamSet p = e->params();
  p.set("gain", 0.9);
  p.set("bias_x_px", 0.3);
  p.set("bias_y_px", -0.2);
  e->set_params(p);  // threshold stays 0.5 px
  std::vector<Vec2> f = {Vec2(2.0, 0.0), Vec2(0.3, 0.0)};
  e->apply(context_for(nullptr), f);
  CHECK((f[0] - Vec2(0.9 * 2.0 + 0.3, -0.2)).norm() < kExact);
  CHECK((f[1] - Vec2(0.9 * 0.3, 0.0)).norm() < kExact);
}

TEST_CASE("camera_misalignment rotates and scales displacements", "[effects]") {
  auto e = make_effect("camera_misalignment");
  ParamSet p = e->params();
  p.set("rotation_rad", 0.1);
  p.set("scale", 1.1);
  e->set_params(p);
  const Vec2 out = apply_one(*e, context_for(nullptr), {Vec2(1.0, 0.0)}, 0);
  CHECK((out - 1.1 * Vec2(std::cos(0.1), std::sin(0.1))).norm() < kExact);
}

TEST_CASE("effects compose in order inside EffectModel", "[effects]") {
  // tracker_bias then load_stiffening: (g d + b) / (1 + beta delta); the other order differs.
  const auto sensor = make_grid_sensor();
  auto m = wrap_with_effects(std::make_unique<FixedFieldModel>(test_field(9)), {"tracker_bias", "load_stiffening"},
                             sensor, make_test_indenter());
  ParamSet p = m->params();
  p.set("tracker_bias.gain", 1.2);
  p.set("tracker_bias.bias_x_px", 1.0);
  p.set("load_stiffening.beta_per_m", 1000.0);
  m->set_params(p);
  FieldOutput o;
  m->step(pressed(0.001), kDt, &o);  // depth 1 mm: 1 + 1000 * 0.001 = 2
  const Vec2 d0 = test_field(9)[0];  // (1, -2), moving
  CHECK((o.disp_px[0] - (1.2 * d0 + Vec2(1.0, 0.0)) / 2.0).norm() < kExact);
}

TEST_CASE("tool_frame: a tilt about a pivot h below the apex moves the indenter by h (R z - z)", "[effects]") {
  // R = Rx(t): R z = (0, -sin t, cos t), so the correction is h (0, -sin t, cos t - 1). At t = 60 deg and
  // h = 4 mm: (0, -3.4641, -2.0) mm. A twist (about z) has R z = z: no correction.
  auto e = make_effect("tool_frame");
  REQUIRE(e->acts_on_pose());
  CHECK(e->needs_tilt());
  ParamSet p = e->params();
  constexpr double h = 0.004, t = std::numbers::pi / 3.0;
  p.set("pivot_depth_m", h);
  e->set_params(p);
  Pose tilted = pressed(-0.001, 0.001, 0.0);
  tilted.linear() = Eigen::AngleAxisd(t, Vec3::UnitX()).toRotationMatrix();
  const Vec3 expected = tilted.translation() + h * Vec3(0.0, -std::sin(t), std::cos(t) - 1.0);
  CHECK((e->corrected_pose(tilted).translation() - expected).norm() < kDepthTol);
  CHECK(e->corrected_pose(tilted).linear().isApprox(tilted.linear(), 0.0));
  Pose twisted = pressed(0.001);
  twisted.linear() = Eigen::AngleAxisd(0.3, Vec3::UnitZ()).toRotationMatrix();
  CHECK((e->corrected_pose(twisted).translation() - twisted.translation()).norm() < kDepthTol);

  SECTION("the base model steps at the corrected pose") {
    // 1 mm above the pad uncorrected (no contact, no field); corrected, 1 mm lower: the centre sits at
    // z = R + 1 mm - 2 mm < R, in contact, so the fixed field appears.
    const auto sensor = make_grid_sensor();
    auto m = wrap_with_effects(std::make_unique<FixedFieldModel>(test_field(9)), {"tool_frame"}, sensor,
                               make_test_indenter());
    FieldOutput o;
    m->step(tilted, kDt, &o);
    CHECK(o.disp_px[0].norm() == 0.0);
    ParamSet mp = m->params();
    mp.set("tool_frame.pivot_depth_m", h);
    m->set_params(mp);
    m->reset();
    m->step(tilted, kDt, &o);
    CHECK((o.disp_px[0] - test_field(9)[0]).norm() < kExact);
  }
}

TEST_CASE("tool_frame: a zero d0 past the skin presses every pose d0 deeper along the surface's normal", "[effects]") {
  // The surface's normal is the indenter's +z, R z in E; deeper is along -R z. Untilted: z drops by d0. Tilted by
  // t = 60 deg about x: R z = (0, -sin t, cos t), so the translation moves by -d0 (0, -sin t, cos t), at d0 = 1.5 mm
  // (0, +1.2990, -0.75) mm. With a pivot h too the two corrections add: h (R z - z) - d0 R z.
  auto e = make_effect("tool_frame");
  ParamSet p = e->params();
  constexpr double d0 = 0.0015, h = 0.004, t = std::numbers::pi / 3.0;
  p.set("press_offset_m", d0);
  e->set_params(p);
  const Pose flat = pressed(0.001);
  CHECK((e->corrected_pose(flat).translation() - (flat.translation() - Vec3(0.0, 0.0, d0))).norm() < kDepthTol);
  Pose tilted = pressed(-0.001, 0.001, 0.0);
  tilted.linear() = Eigen::AngleAxisd(t, Vec3::UnitX()).toRotationMatrix();
  const Vec3 approach(0.0, -std::sin(t), std::cos(t));
  CHECK((e->corrected_pose(tilted).translation() - (tilted.translation() - d0 * approach)).norm() < kDepthTol);
  CHECK(e->corrected_pose(tilted).linear().isApprox(tilted.linear(), 0.0));
  p.set("pivot_depth_m", h);
  e->set_params(p);
  const Vec3 both = tilted.translation() + h * (approach - Vec3::UnitZ()) - d0 * approach;
  CHECK((e->corrected_pose(tilted).translation() - both).norm() < kDepthTol);
}

TEST_CASE("pin_lever: a pin under a sphere turns with the sphere's face, one outside does not", "[effects]") {
  // Sphere of radius R = 4 mm pressed 1 mm: centre c = (0, 0, 3 mm). A marker at (1.5, 0, 0) mm is inside it;
  // the skin there takes the sphere's face, n_new = -(p - c)/|p - c| = (-1.5, 0, 3)/3.3541 (mm), against
  // n_rest = z. A pin of length L = 1 mm following with g = 1 moves by -L (n_new - z), x: 1.5/3.3541 mm =
  // 0.44721 mm = 7.0538 px at the default 0.0634 mm/px. A marker at (3, 0, 0) mm is 4.243 mm from c: outside.
  auto sensor = make_test_sensor({Vec2(0.0015, 0.0), Vec2(0.003, 0.0)});
  sensor->gel.markers_depth_m = 0.001;
  const auto sphere = make_test_indenter();
  auto e = make_effect("pin_lever");
  REQUIRE(e->acts_on(*sensor));
  ParamSet p = e->params();
  p.set("gain", 1.0);
  e->set_params(p);
  EffectContext ctx = context_for(sensor.get(), 0.001, true);
  ctx.indenter = sphere.get();
  ctx.X_EI = pressed(0.001);
  std::vector<Vec2> d = {Vec2(0.5, 0.0), Vec2(0.5, 0.0)};
  e->apply(ctx, d);
  const double expected_px = 1.5 / std::sqrt(1.5 * 1.5 + 3.0 * 3.0) / 0.0634;
  CHECK((d[0] - Vec2(0.5 + expected_px, 0.0)).norm() < 1e-9);  // px: the SDF's gradient is exact
  CHECK((d[1] - Vec2(0.5, 0.0)).norm() == 0.0);
  sensor->gel.markers_depth_m = 0.0;  // pins on the surface: the identity, and the loop does not try it
  CHECK_FALSE(e->acts_on(*sensor));
}

TEST_CASE("EffectModel: steps without a field leave the loading state and the penetration as with one", "[effects]") {
  // Depths 0.5, 1.0, 1.0 mm then 0.4 mm with a field: unloading from the step before (1.0 mm) whether or not
  // that step computed its field; last_penetration() after a step without a field is that step's.
  const auto make = [] {
    std::vector<std::unique_ptr<Effect>> fx;
    fx.push_back(std::make_unique<RecordingEffect>());
    return EffectModel(std::make_unique<FixedFieldModel>(test_field(9)), std::move(fx), make_grid_sensor(),
                       make_test_indenter());
  };
  EffectModel with_fields = make(), sparse = make();
  const std::vector<double> depths = {0.0005, 0.001, 0.001, 0.0004, 0.0008};
  FieldOutput a, b;
  for (std::size_t k = 0; k < depths.size(); ++k) {
    with_fields.step(pressed(depths[k]), kDt, &a);
    const bool field = k == 3 || k == 4;
    sparse.step(pressed(depths[k]), kDt, field ? &b : nullptr);
    if (k == 2) CHECK(std::abs(sparse.last_penetration().depth_m - 0.001) < kDepthTol);
  }
  const auto& all = dynamic_cast<const RecordingEffect&>(with_fields.effect(0)).seen;
  const auto& some = dynamic_cast<const RecordingEffect&>(sparse.effect(0)).seen;
  REQUIRE(some.size() == 2);
  CHECK(!some[0].loading);  // 1.0 -> 0.4 mm
  CHECK(some[1].loading);   // 0.4 -> 0.8 mm
  CHECK(some[0].depth_m == all[3].depth_m);
  CHECK(some[1].time_s == all[4].time_s);
  CHECK(b.disp_px == a.disp_px);
}

TEST_CASE("dome_sway: the slide in contact, clipped at the stick length, shifts every pin of a flat gel alike",
          "[effects]") {
  // Flat pad: every pin has polar angle 0 (w = 1) and the contact normal is z (no tilt load). With c = 0.1 mm,
  // mu = 0.5, q = 2 at 1 mm depth (load 1): u = c mu s, s = travel / t0 with |travel| <= t0 = 0.3 mm.
  //   slid 0.1 mm: u = 0.1 * 0.5 * (0.1 / 0.3) mm = 0.0166667 mm = 0.262881 px at 0.0634 mm/px;
  //   slid 0.5 mm: clipped, u = 0.05 mm = 0.788644 px. Lifted out of contact and pressed again: no slide, no shift.
  const auto sensor = make_grid_sensor();
  auto m =
      wrap_with_effects(std::make_unique<FixedFieldModel>(test_field(9)), {"dome_sway"}, sensor, make_test_indenter());
  ParamSet p = m->params();
  p.set("dome_sway.compliance_m", 1e-4);
  p.set("dome_sway.friction", 0.5);
  m->set_params(p);
  constexpr double kPxPerM = 1.0 / 0.0634e-3;
  FieldOutput o;
  const auto shift_after = [&](const Pose& X_EI) {
    m->step(X_EI, kDt, &o);
    return Vec2(o.disp_px[4] - test_field(9)[4]);
  };
  CHECK(shift_after(pressed(0.001)).norm() < kExact);
  CHECK((shift_after(pressed(0.001, 0.0001)) - Vec2(0.0166667e-3 * kPxPerM, 0.0)).norm() < 1e-4);
  m->step(pressed(0.001, 0.0003), kDt, nullptr);  // a step without a field still counts the slide
  CHECK((shift_after(pressed(0.001, 0.0005)) - Vec2(0.05e-3 * kPxPerM, 0.0)).norm() < 1e-9);
  CHECK((o.disp_px[0] - test_field(9)[0] - Vec2(0.05e-3 * kPxPerM, 0.0)).norm() < 1e-9);  // all pins alike
  m->step(pressed(-0.001, 0.0005), kDt, nullptr);  // lifted: the slide starts again at the next contact
  CHECK(shift_after(pressed(0.001, 0.0005)).norm() < kExact);
  SECTION("a clone carries the slide") {
    m->step(pressed(0.001, 0.0007), kDt, &o);
    auto copy = m->clone();
    FieldOutput oc;
    m->step(pressed(0.001, 0.0008), kDt, &o);
    copy->step(pressed(0.001, 0.0008), kDt, &oc);
    CHECK(oc.disp_px == o.disp_px);
  }
}

TEST_CASE("dome_sway: a normal load off the apex of a dome pushes the tip away, the pins by cos(pi/2 theta/90 deg)",
          "[effects]") {
  // Hemisphere R = 20 mm (rim at 90 deg). The contact centre at xy = (10, 0) mm projects onto the sphere along
  // (10, 0, 20)/22.3607: n_xy = (1/sqrt 5, 0). At depth 2 mm with q = 2 the load is 4, so with c = 0.1 mm and no
  // slide the apex shift is u = -0.4/sqrt(5) mm = -0.178885 mm = -2.821532 px (orthographic, 0.0634 mm/px); a pin
  // at polar angle 45 deg moves by cos(pi/4) of it, -1.995108 px. Nothing along y.
  constexpr double R = 0.02, kPxPerM = 1.0 / 0.0634e-3;
  auto s = std::make_shared<Sensor>();
  s->gel.surface = "spherical_cap";
  s->gel.radius_m = R;
  s->gel.footprint_radius_m = R;
  s->gel.thickness_m = 0.025;
  s->gel_sdf = make_spherical_cap_sdf(R, R, 0.025);
  const double q = R * std::sqrt(0.5);
  s->p_EM = {Vec3(0, 0, 0), Vec3(q, 0, q - R)};
  for (const Vec3& p : s->p_EM) s->markers_rest_px.push_back(s->camera.px_from_E(p.head<2>()));
  auto e = make_effect("dome_sway");
  ParamSet p = e->params();
  p.set("compliance_m", 1e-4);
  e->set_params(p);
  EffectContext ctx = context_for(s.get(), 0.002, true);
  ctx.contact_centre_E = Vec2(0.01, 0.0);
  std::vector<Vec2> d(2, Vec2::Zero());
  e->apply(ctx, d);
  const double apex_px = -0.4e-3 / std::sqrt(5.0) * kPxPerM;
  // The normals are central differences of the SDF with h = 10 um: relative error ~ (h / R)^2 = 2.5e-7, i.e.
  // 7e-7 px of 2.8 px.
  constexpr double kFdNormalTolPx = 2e-6;
  CHECK((d[0] - Vec2(apex_px, 0.0)).norm() < kFdNormalTolPx);
  CHECK((d[1] - Vec2(std::cos(std::numbers::pi / 4) * apex_px, 0.0)).norm() < kFdNormalTolPx);
  SECTION("the tip turns towards the load about a point on its axis") {
    // No shift; r = 4 mrad per unit load, centre 20 mm below the apex. The load (-4/sqrt 5, 0) turns the tip by
    // theta = 0.016/sqrt(5) = 0.0071554175 rad about -y (z x load = (0, -4/sqrt 5, 0)): p - c = (x, 0, z) goes to
    // (x cos theta - z sin theta, 0, ...). Apex (0, 0, 20) mm: dx = -20 sin theta mm = -2.2572102 px; the pin at
    // 45 deg, (14.142136, 0, 14.142136) mm: dx = 14.142136 (cos theta - 1 - sin theta) mm = -1.6017990 px.
    p.set("compliance_m", 0.0);
    p.set("rotation_rad", 0.004);
    p.set("centre_depth_m", 0.02);
    e->set_params(p);
    std::vector<Vec2> t(2, Vec2::Zero());
    e->apply(ctx, t);
    CHECK((t[0] - Vec2(-2.2572102, 0.0)).norm() < kFdNormalTolPx);
    CHECK((t[1] - Vec2(-1.6017990, 0.0)).norm() < kFdNormalTolPx);
  }
  SECTION("friction off the axis, or a twisting contact, twists the dome about its axis") {
    // No shift, no turn; k = 1 mrad per unit torque, mu = 1, load 4 (2 mm, q = 2), stick 0.3 mm.
    // Slid 0.1 mm along y with the contact centre at (10, 0) mm: s = (0, 1/3), torque 4 (10 x 1/3) = 13.333333,
    // twist 0.0133333 rad; the apex pin is on the axis (still), the 45 deg pin at 14.142136 mm turns by
    // cos(pi/4) of it, a = 0.0094280904 rad: dx = 14.142136 (cos a - 1) mm = -0.0099137966 px,
    // dy = 14.142136 sin a mm = 2.1030183 px.
    p.set("compliance_m", 0.0);
    p.set("torsion_rad", 0.001);
    e->set_params(p);
    Penetration pen;
    pen.penetrating = true;
    pen.depth_m = 0.002;
    Pose X = Pose::Identity();
    e->observe_step(X, pen);
    X.translation() = Vec3(0.0, 1e-4, 0.0);
    e->observe_step(X, pen);
    std::vector<Vec2> t(2, Vec2::Zero());
    e->apply(ctx, t);
    CHECK(t[0].norm() < kFdNormalTolPx);
    CHECK((t[1] - Vec2(-0.0099137966, 2.1030183)).norm() < kFdNormalTolPx);
    // Turned 2 mrad in place at the axis: the contact's mean lever on the cap rho = 2/3 sqrt(2 R delta) =
    // 5.9628479 mm, its arc 0.011926 mm of the 0.3 mm stick (s_psi = 0.039752320), torque 4 rho s_psi = 0.94814815:
    // the 45 deg pin moves dx = -5.0132358e-5 px, dy = 0.14955017 px.
    e->reset();
    ctx.contact_centre_E = Vec2::Zero();
    e->observe_step(Pose::Identity(), pen);
    X = Pose::Identity();
    X.linear() = Eigen::AngleAxisd(0.002, Vec3::UnitZ()).toRotationMatrix();
    e->observe_step(X, pen);
    std::vector<Vec2> w(2, Vec2::Zero());
    e->apply(ctx, w);
    CHECK(w[0].norm() < kFdNormalTolPx);
    CHECK((w[1] - Vec2(-5.0132358e-5, 0.14955017)).norm() < kFdNormalTolPx);
  }
  SECTION("no compliance, no contact: the identity") {
    std::vector<Vec2> z(2, Vec2(1.0, 2.0));
    p.set("compliance_m", 0.0);
    e->set_params(p);
    e->apply(ctx, z);
    CHECK(z == std::vector<Vec2>(2, Vec2(1.0, 2.0)));
  }
}

TEST_CASE("spread_saturation: markers inside a pressed sphere lose the spread of their depth beyond h0 tanh(h/h0)",
          "[effects]") {
  // Sphere R = 4 mm pressed 2 mm: centre c = (0, 0, 2) mm. Marker A at the origin is 2 mm inside it (h_A = 4 - 2);
  // B at (1.5, 0, 0) mm is sqrt(1.5^2 + 2^2) = 2.5 mm from c, h_B = 1.5 mm. With g = 1 px, h0 = 1 mm, sigma = 2 mm
  // the lost depths are tanh(2) - 2 = -1.0359724 and tanh(1.5) - 1.5 = -0.5948517 (mm), the kernel between them
  // exp(-1.5^2 / (2 * 2^2)) = 0.7548396, so
  //   A += g (h_B lost) (m_A - m_B) w = (-0.5948517)(-1.5)(0.7548396) = +0.6735265 px along x,
  //   B += g (h_A lost) (m_B - m_A) w = (-1.0359724)(+1.5)(0.7548396) = -1.1729895 px along x;
  // a marker's own term has zero offset. A marker C at (6, 0, 0) mm is outside the sphere and adds nothing.
  constexpr double kTol = 1e-9;  // px: closed-form distances, a few roundings
  auto sensor = make_test_sensor({Vec2(0.0, 0.0), Vec2(0.0015, 0.0), Vec2(0.006, 0.0)});
  const auto sphere = make_test_indenter();
  auto e = make_effect("spread_saturation");
  ParamSet p = e->params();
  p.set("gain_px", 1.0);
  p.set("depth_scale_m", 0.001);
  p.set("width_m", 0.002);
  e->set_params(p);
  EffectContext ctx = context_for(sensor.get(), 0.002, true);
  ctx.indenter = sphere.get();
  ctx.X_EI = pressed(0.002);
  std::vector<Vec2> d(3, Vec2(0.25, -0.5));
  e->apply(ctx, d);
  const double w_AC = std::exp(-6.0 * 6.0 / 8.0), w_BC = std::exp(-4.5 * 4.5 / 8.0);
  CHECK((d[0] - Vec2(0.25 + 0.6735264831917626, -0.5)).norm() < kTol);
  CHECK((d[1] - Vec2(0.25 - 1.1729895136907387, -0.5)).norm() < kTol);
  // C feels both inside markers: (h_A lost)(6) w_AC + (h_B lost)(4.5) w_BC.
  const double c_x = -1.035972419924183 * 6.0 * w_AC - 0.5948517463551336 * 4.5 * w_BC;
  CHECK((d[2] - Vec2(0.25 + c_x, -0.5)).norm() < kTol);
  // At its default gain the effect is the identity; out of contact (sphere lifted) too.
  ctx.X_EI = pressed(-0.001);
  std::vector<Vec2> lifted(3, Vec2(0.25, -0.5));
  e->apply(ctx, lifted);
  CHECK(lifted == std::vector<Vec2>(3, Vec2(0.25, -0.5)));
}

TEST_CASE("skin_indentation: pins under a pressed sphere go in along the dome's normal, towards the principal point",
          "[effects]") {
  // Hemisphere R = 20 mm, pins L = 3 mm deep, pinhole camera f = 400 px, D = 50 mm, c = (200, 200) px; the test
  // sphere (r = 4 mm) pressed 2 mm at the apex, centre (0, 0, 2) mm. Pins at sin(t) = 0, 0.1, 0.3 on the dome:
  // p = (R sin t, 0, R cos t - R), n = (sin t, 0, cos t), h = relu(r - |p - centre|): 2, 1.0998180 and 0 mm.
  // Gain 1, no spread: tip = p - L n moves by -h n. The apex pin moves along the principal ray (no image motion).
  // Pin B: tip (1.7, 0, -3.0852136) mm -> (1.5900182, 0, -4.1795187) mm, u - c = f x / (z + D):
  // 400 * 1.7 / 46.9147864 = 14.4943660 -> 400 * 1.5900182 / 45.8204813 = 13.8804164 px: -0.6139496 px.
  // Pin C is outside the sphere (|p - centre| = 5.46 mm): nothing.
  constexpr double R = 0.02, L = 0.003;
  constexpr double kTolPx = 2e-6;  // the rest normals are central differences of the SDF (h = 10 um), ~1e-7 px
  auto s = std::make_shared<Sensor>();
  s->gel.surface = "spherical_cap";
  s->gel.radius_m = R;
  s->gel.footprint_radius_m = R;
  s->gel.thickness_m = 0.025;
  s->gel.markers_depth_m = L;
  s->gel_sdf = make_spherical_cap_sdf(R, R, 0.025);
  s->camera.model = CameraModel::kPinhole;
  s->camera.focal_px = 400.0;
  s->camera.distance_m = 0.05;
  s->camera.principal_px = Vec2(200.0, 200.0);
  for (const double sin_t : {0.0, 0.1, 0.3})
    s->p_EM.push_back(Vec3(R * sin_t, 0.0, R * std::sqrt(1.0 - sin_t * sin_t) - R));
  for (const Vec3& p : s->p_EM) s->markers_rest_px.push_back(s->camera.project(p));
  const auto sphere = make_test_indenter();
  auto e = make_effect("skin_indentation");
  CHECK(e->acts_on(*s));
  CHECK_FALSE(e->acts_on(*make_test_sensor({Vec2(0.0, 0.0)})));  // orthographic: the normal motion is invisible
  ParamSet p = e->params();
  p.set("gain", 1.0);
  e->set_params(p);
  EffectContext ctx = context_for(s.get(), 0.002, true);
  ctx.indenter = sphere.get();
  ctx.X_EI = pressed(0.002);
  std::vector<Vec2> d(3, Vec2(0.25, -0.5));
  e->apply(ctx, d);
  CHECK((d[0] - Vec2(0.25, -0.5)).norm() < kTolPx);
  CHECK((d[1] - Vec2(0.25 - 0.6139496, -0.5)).norm() < kTolPx);
  CHECK((d[2] - Vec2(0.25, -0.5)).norm() < kTolPx);
  SECTION("a spread of 2 mm shares the indentation with the neighbours, the outside pin included") {
    // w = K h, K_jk = exp(-|p_j - p_k|^2 / (2 (2 mm)^2)) normalised per row: w = (1.6501434, 1.3359130, 0.1382238)
    // mm; imaged as above: 0, -0.7495874 and -0.2336271 px.
    p.set("spread_m", 0.002);
    e->set_params(p);
    std::vector<Vec2> w(3, Vec2::Zero());
    e->apply(ctx, w);
    CHECK(w[0].norm() < kTolPx);
    CHECK((w[1] - Vec2(-0.7495874, 0.0)).norm() < kTolPx);
    CHECK((w[2] - Vec2(-0.2336271, 0.0)).norm() < kTolPx);
  }
  SECTION("the sphere lifted: the identity") {
    ctx.X_EI = pressed(-0.001);
    std::vector<Vec2> lifted(3, Vec2(0.25, -0.5));
    e->apply(ctx, lifted);
    CHECK(lifted == std::vector<Vec2>(3, Vec2(0.25, -0.5)));
  }
}

}  // namespace test_effects
