// Fingerprints (core/loop/fingerprints.hpp): each effect's main parameter estimated from the evidence that a
// base model's form error cannot fake. Synthetic series with known parameters, then the same series with the
// kind of error the fingerprint claims to see through (and, for lens and subsurface, a model-form-like error:
// a smooth residual concentrated near the contact).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/effects/effects.hpp"
#include "core/loop/fingerprints.hpp"
#include "core/loop/rest_grid_lens.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_fingerprints {

using sb::FingerprintSample;
using sb::Vec2;

namespace {

using Series = std::vector<std::vector<Vec2>>;  // [frame][marker]

const sb::Sensor& sensor() {
  static const sb::Sensor s = sb::make_default_sensor();  // 7 x 9 markers at 33 px = 2.09 mm
  return s;
}

// Runs `effect` at `params` over a series frame by frame (as the effect wraps a model).
Series apply_effect(const std::string& effect, const std::map<std::string, double>& params, const Series& in,
                    double dt_s, const sb::Sensor& on = sensor()) {
  auto e = sb::make_effect(effect);
  sb::ParamSet p = e->params();
  for (const auto& [name, value] : params) p.set(name, value);
  e->set_params(p);
  e->reset();
  sb::EffectContext ctx;
  ctx.sensor = &on;
  Series out = in;
  for (std::size_t k = 0; k < out.size(); ++k) {
    ctx.dt_s = k == 0 ? 0.0 : dt_s;
    e->apply(ctx, out[k]);
  }
  return out;
}

void add_noise(Series* s, double sigma, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0.0, sigma);
  for (auto& f : *s)
    for (auto& d : f) {
      const double dx = n(rng);  // two statements: argument order is unspecified (gcc and clang differ)
      d += Vec2(dx, n(rng));
    }
}

// ------------------------------------------------------------------------------------------ creep

// A press of `amplitude` px (marker j moves amplitude * (j % 7 + 1) / 7 along x and half that along y):
// 5 frames free, a 10-frame ramp, a held press of `hold` frames, a 10-frame release, 30 frames free.
struct Press {
  Series glassy;
  std::vector<std::uint8_t> in_contact, held;
};

Press press_series(double amplitude, int hold) {
  Press p;
  const std::size_t M = sensor().markers_rest_px.size();
  std::vector<double> level;
  for (int k = 0; k < 5; ++k) level.push_back(0);
  for (int k = 1; k <= 10; ++k) level.push_back(k / 10.0);
  for (int k = 0; k < hold; ++k) level.push_back(1);
  for (int k = 9; k >= 0; --k) level.push_back(k / 10.0);
  for (int k = 0; k < 30; ++k) level.push_back(0);
  for (std::size_t k = 0; k < level.size(); ++k) {
    std::vector<Vec2> f(M);
    for (std::size_t j = 0; j < M; ++j) f[j] = amplitude * level[k] * (j % 7 + 1) / 7.0 * Vec2(1.0, 0.5);
    p.glassy.push_back(f);
    p.in_contact.push_back(level[k] > 0);
    p.held.push_back(k > 0 && level[k] == 1 && level[k - 1] == 1);
  }
  return p;
}

FingerprintSample creep_sample(const Press& p, const Series& meas, double dt) {
  FingerprintSample s;
  s.dt_s = dt;
  s.meas_px = meas;
  s.in_contact = p.in_contact;
  s.held = p.held;
  return s;
}

}  // namespace

TEST_CASE("sls_glassy_field undoes the viscoelastic_creep effect", "[fingerprints]") {
  // One marker, a step to D = 2 px at frame 1, held; dt = 0.1 s, tau = 0.2 s, c = 0.5, a = exp(-0.5).
  // Forward (docs/effects.md): x_1 = c d_0 (1 - a) = 0, so meas_1 = D; x_2 = c D (1 - a), meas_2 = D (1 + c (1 - a));
  // x_3 = c D (1 - a) + a x_2 = c D (1 - a^2), meas_3 = D (1 + c (1 - a^2)). Undone: D on every frame >= 1.
  constexpr double kExact = 1e-12;
  const double D = 2.0, c = 0.5, a = std::exp(-0.5);
  const Series meas = {
      {Vec2(0, 0)}, {Vec2(D, 0)}, {Vec2(D * (1 + c * (1 - a)), 0)}, {Vec2(D * (1 + c * (1 - a * a)), 0)}};
  const Series d = sb::sls_glassy_field(meas, 0.1, 0.2, c);
  CHECK(d[0][0].norm() < kExact);
  for (int k = 1; k < 4; ++k) CHECK((d[k][0] - Vec2(D, 0)).norm() < kExact);
  // On a whole press through the effect itself (every marker), it returns the glassy series.
  const Press p = press_series(6.0, 20);
  const Series filtered = apply_effect("viscoelastic_creep", {{"tau_s", 0.3}, {"creep_fraction", 0.3}}, p.glassy, 0.02);
  const Series back = sb::sls_glassy_field(filtered, 0.02, 0.3, 0.3);
  for (std::size_t k = 0; k < back.size(); ++k)
    for (std::size_t j = 0; j < back[k].size(); ++j) CHECK((back[k][j] - p.glassy[k][j]).norm() < 1e-9);
  CHECK_THROWS_AS(sb::sls_glassy_field(meas, 0.1, 0.0, c), std::invalid_argument);
}

TEST_CASE("creep fingerprint: an SLS-filtered held press gives tau and c back", "[fingerprints]") {
  // tau 0.3 s, c 0.3 at 50 Hz, a 1 s hold, 0.05 px tracker noise: over the hold the field grows by
  // c (1 - exp(-1 / 0.3)) = 29 % of itself (1.7 px at the 6 px markers) and after release the same decays; noise
  // alone drifts ~0.1 px. Both parameters must come back within 5 % (the grid's pattern search stops at
  // 1e-3 of a cell; the rest is noise).
  constexpr double kRelTol = 0.05;
  const Press p = press_series(6.0, 50);
  Series meas = apply_effect("viscoelastic_creep", {{"tau_s", 0.3}, {"creep_fraction", 0.3}}, p.glassy, 0.02);
  add_noise(&meas, 0.05, 1);
  const sb::CreepFingerprint f = sb::creep_fingerprint({creep_sample(p, meas, 0.02)});
  INFO("tau " << f.tau_s << " c " << f.creep_fraction << " signal " << f.signal_rms_px << " explained "
              << f.explained_pct);
  CHECK(std::abs(f.tau_s - 0.3) < kRelTol * 0.3);
  CHECK(std::abs(f.creep_fraction - 0.3) < kRelTol * 0.3);
  CHECK(f.signal_rms_px > 0.15);
  CHECK(f.explained_pct > 90);

  SECTION("not fooled by a permanent set, lost markers or a field of another shape") {
    // Adhesion leaves 0.5 px on every marker that moved from release on (constant: the release evidence is
    // the change since release); a third of the markers are lost on every fifth frame; a model-form-like
    // pattern (what a wrong base model would miss: 1 px more on odd markers) is in the glassy field
    // whenever the indenter is in the gel, held or not. None changes while the pose is held.
    Press q = press_series(6.0, 50);
    for (std::size_t k = 0; k < q.glassy.size(); ++k)
      for (std::size_t j = 0; j < q.glassy[k].size(); ++j)
        if (q.in_contact[k] && j % 2) q.glassy[k][j] += Vec2(0, 1.0);
    Series m = apply_effect("viscoelastic_creep", {{"tau_s", 0.3}, {"creep_fraction", 0.3}}, q.glassy, 0.02);
    bool released = false;
    for (std::size_t k = 0; k < m.size(); ++k) {
      released = released || (k > 0 && q.in_contact[k - 1] && !q.in_contact[k]);
      for (std::size_t j = 0; j < m[k].size(); ++j) {
        if (released) m[k][j] += Vec2(0.5, 0.0);
        if (k % 5 == 0 && j % 3 == 0) m[k][j] = Vec2(NAN, NAN);
      }
    }
    add_noise(&m, 0.05, 2);
    const sb::CreepFingerprint g = sb::creep_fingerprint({creep_sample(q, m, 0.02)});
    INFO("tau " << g.tau_s << " c " << g.creep_fraction);
    CHECK(std::abs(g.tau_s - 0.3) < kRelTol * 0.3);
    CHECK(std::abs(g.creep_fraction - 0.3) < kRelTol * 0.3);
  }

  SECTION("an elastic gel has no creep fingerprint") {
    Series still = p.glassy;
    add_noise(&still, 0.05, 3);
    const FingerprintSample s = creep_sample(p, still, 0.02);
    const sb::CreepFingerprint g = sb::creep_fingerprint({s});
    CHECK(g.signal_rms_px < 0.15);  // noise: sqrt(2) sigma per component difference = 0.1 px
    const auto check = sb::fingerprint_check("viscoelastic_creep", sensor(), {s}, {s});
    REQUIRE(check.has_value());
    CHECK_FALSE(check->consistent);
    CHECK(check->verdict.find("above noise") != std::string::npos);
  }

  SECTION("the finding: both splits agree, the fit holds tau and c") {
    Series other = apply_effect("viscoelastic_creep", {{"tau_s", 0.3}, {"creep_fraction", 0.3}},
                                press_series(4.0, 40).glassy, 0.02);
    add_noise(&other, 0.05, 4);
    const auto check = sb::fingerprint_check("viscoelastic_creep", sensor(), {creep_sample(p, meas, 0.02)},
                                             {creep_sample(press_series(4.0, 40), other, 0.02)});
    REQUIRE(check.has_value());
    CHECK(check->consistent);
    CHECK(check->beyond_model_form);
    REQUIRE(check->held.size() == 2);
    CHECK(check->held[0].first == "tau_s");
    CHECK(check->held[0].second == Approx(f.tau_s));
    // A validation split whose creep is twice as slow disagrees (ratio 2 > 1.5).
    Series slow = apply_effect("viscoelastic_creep", {{"tau_s", 0.6}, {"creep_fraction", 0.3}}, p.glassy, 0.02);
    add_noise(&slow, 0.05, 5);
    const auto split = sb::fingerprint_check("viscoelastic_creep", sensor(), {creep_sample(p, meas, 0.02)},
                                             {creep_sample(p, slow, 0.02)});
    CHECK_FALSE(split->consistent);
    CHECK(split->verdict.find("disagree") != std::string::npos);
  }
}

// ------------------------------------------------------------------------------------------- lens

namespace {

// A press and twist of an axisymmetric indenter at `centre_px`: the field is symmetric about the contact,
// radial part A s exp(1/2 - s^2/2) (s = rho / 40 px, peak A at 40 px) and tangential part B times the same
// profile, both growing over 12 frames.
FingerprintSample axisymmetric_press(const Vec2& centre_px, double A, double B, const sb::Sensor& on = sensor()) {
  FingerprintSample s;
  const auto& m = on.markers_rest_px;
  for (int k = 1; k <= 12; ++k) {
    std::vector<Vec2> f(m.size());
    for (std::size_t j = 0; j < m.size(); ++j) {
      const Vec2 out = m[j] - centre_px;
      const double rho = out.norm(), sc = rho / 40.0;
      const Vec2 radial = rho > 0 ? Vec2(out / rho) : Vec2(1, 0), tangential(-radial.y(), radial.x());
      const double profile = sc * std::exp(0.5 - 0.5 * sc * sc) * k / 12.0;
      f[j] = profile * (A * radial + B * tangential);
    }
    s.meas_px.push_back(f);
    s.pred_px.push_back(f);
    s.in_contact.push_back(1);
    s.held.push_back(0);
    s.contact_centre_px.push_back(centre_px);
    s.travel_px.push_back(0.0);
  }
  return s;
}

// The samples as a camera with lens k1 sees them (the effect on each frame); pred stays the undistorted field.
std::vector<FingerprintSample> through_lens(std::vector<FingerprintSample> samples, double k1,
                                            const sb::Sensor& on = sensor()) {
  for (auto& s : samples) s.meas_px = apply_effect("lens_distortion", {{"k1", k1}}, s.meas_px, 0.02, on);
  return samples;
}

// The default sensor with its rest grid no longer a lattice (each marker moved by up to a fifth of the pitch
// along a fixed pseudo-random direction; p_EM kept): the lens fingerprint falls back on the residual.
const sb::Sensor& scattered_sensor() {
  static const sb::Sensor s = [] {
    sb::Sensor out = sb::make_default_sensor();
    for (std::size_t j = 0; j < out.markers_rest_px.size(); ++j) {
      const double a = 2.399963 * double(j);  // the golden angle: no two directions alike
      out.markers_rest_px[j] += 6.6 * std::fmod(0.618034 * double(j), 1.0) * Vec2(std::cos(a), std::sin(a));
    }
    return out;
  }();
  return s;
}

// A contact model's error of a press: symmetric about the contact, 1 px radial, wider than the field
// (peak at 70 px), plus a uniform 0.3 px offset.
void add_symmetric_model_error(FingerprintSample* s) {
  const auto& m = sensor().markers_rest_px;
  for (std::size_t k = 0; k < s->pred_px.size(); ++k)
    for (std::size_t j = 0; j < m.size(); ++j) {
      const Vec2 out = m[j] - s->contact_centre_px[k];
      const double rho = out.norm(), sc = rho / 70.0;
      const Vec2 radial = rho > 0 ? Vec2(out / rho) : Vec2(1, 0);
      s->pred_px[k][j] += (k + 1) / 12.0 * (sc * std::exp(0.5 - 0.5 * sc * sc) * radial + Vec2(0.3, 0.0));
    }
}

}  // namespace

TEST_CASE("lens fingerprint: k1 from the residual that is not symmetric about the contact", "[fingerprints]") {
  // The pattern is the effect's k1 term: at rest m = (259.5, 119.5) (r = 100 / 200 = 0.5), a 10 px move along x
  // is seen as D(m + d) - D(m) = 10 + k1 (110^3 - 100^3) / 200^2 = 10 + 8.275 k1 px (the test of the effect).
  CHECK(sb::lens_k1_pattern(sensor().camera, Vec2(259.5, 119.5), Vec2(10, 0)).x() == Approx(8.275).epsilon(1e-12));
  // Two presses off the principal point (the lens's asymmetric part grows with the contact's distance from it).
  const std::vector<FingerprintSample> presses = {axisymmetric_press(Vec2(230, 80), 8.0, 0.0),
                                                  axisymmetric_press(Vec2(90, 160), 6.0, 3.0)};
  // Exact model, k1 = -0.15: the residual is k1 times the pattern of the model's field exactly (k2 = 0), and
  // projecting both on the same nuisance fields keeps that: k1 back to rounding.
  constexpr double kExactModelTol = 1e-9;
  const auto exact = sb::lens_fingerprint(sensor(), through_lens(presses, -0.15));
  INFO("k1 " << exact.k1 << " +- " << exact.k1_stderr << " signal " << exact.signal_rms_px << " px");
  CHECK(std::abs(exact.k1 + 0.15) < kExactModelTol * 0.15);
  CHECK(exact.frames == 24);

  SECTION("not fooled by a symmetric model-form error and noise") {
    // The model is wrong by a smooth, contact-centred field larger than the lens's whole effect (1 px against
    // 0.1-0.4 px) and the tracker adds 0.05 px: k1 within 10 % (the noise's share: stderr ~ 0.005).
    constexpr double kModelErrorTol = 0.10;
    auto seen = through_lens(presses, -0.15);
    std::uint64_t seed = 7;
    for (auto& s : seen) {
      add_symmetric_model_error(&s);
      add_noise(&s.meas_px, 0.05, seed++);
    }
    const auto f = sb::lens_fingerprint(sensor(), seen);
    INFO("k1 " << f.k1 << " +- " << f.k1_stderr);
    CHECK(std::abs(f.k1 + 0.15) < kModelErrorTol * 0.15);
    // The same model error without a lens reads as no lens.
    auto none = presses;
    for (auto& s : none) {
      add_symmetric_model_error(&s);
      add_noise(&s.meas_px, 0.05, seed++);
    }
    const auto z = sb::lens_fingerprint(sensor(), none);
    INFO("k1 without lens " << z.k1 << " +- " << z.k1_stderr);
    CHECK(std::abs(z.k1) < 0.02);
  }

  SECTION("a slide is not used: its field is not symmetric") {
    auto slid = through_lens(presses, -0.15);
    for (auto& s : slid)
      for (auto& t : s.travel_px) t = 5.0;
    CHECK(std::isnan(sb::lens_fingerprint(sensor(), slid).k1));
  }

  SECTION("on a rest grid that is not a lattice, the finding bounds k1 near its estimate and holds k2") {
    const sb::Sensor& on = scattered_sensor();
    REQUIRE(sb::fingerprint_needs_model("lens_distortion", on));
    const std::vector<FingerprintSample> scattered = {axisymmetric_press(Vec2(230, 80), 8.0, 0.0, on),
                                                      axisymmetric_press(Vec2(90, 160), 6.0, 3.0, on)};
    const auto seen = through_lens(scattered, -0.15, on);
    const auto check = sb::fingerprint_check("lens_distortion", on, seen, seen);
    INFO(check->evidence << ": " << check->verdict);
    REQUIRE(check->consistent);
    CHECK(std::abs(check->calibration + 0.15) < kExactModelTol * 0.15);
    CHECK(check->evidence.find("the rest grid is not a lattice") != std::string::npos);
    CHECK_FALSE(check->beyond_model_form);
    REQUIRE(check->band.size() == 1);
    CHECK(check->band[0].low == Approx(check->calibration * 1.5));  // k1 < 0: [1.5 k1, k1 / 1.5]
    CHECK(check->band[0].high == Approx(check->calibration / 1.5));
    REQUIRE(check->held.size() == 1);
    CHECK(check->held[0].first == "k2");
  }
}

TEST_CASE("lens fingerprint: a rest grid that is a lattice is the evidence, whatever the residual says",
          "[fingerprints]") {
  const std::vector<FingerprintSample> presses = {axisymmetric_press(Vec2(230, 80), 8.0, 0.0),
                                                  axisymmetric_press(Vec2(90, 160), 6.0, 3.0)};
  // The default sensor's rest grid is a perfect lattice: k1 = 0 there, so a lens the residual reads (-0.15
  // exactly, test above) is not found, and no model's field is needed.
  REQUIRE_FALSE(sb::fingerprint_needs_model("lens_distortion", sensor()));
  const auto seen = through_lens(presses, -0.15);
  const auto flat = sb::fingerprint_check("lens_distortion", sensor(), seen, seen);
  INFO(flat->verdict);
  CHECK_FALSE(flat->consistent);
  CHECK(flat->verdict.find("rest grid: a lattice of 63 markers") == 0);
  CHECK(flat->verdict.find("not found, k1 is none") != std::string::npos);

  // The rest grid as a lens with k1 = -0.15 images it (p_EM kept: the markers are where they are): found from
  // the rest positions alone (exact: to rounding), the same on both splits, held with k2 = 0, accepted on that
  // evidence; the residual of presses without any lens does not matter.
  sb::Sensor bent = sb::make_default_sensor();
  for (Vec2& m : bent.markers_rest_px) m = sb::lens_distort_px(bent.camera, -0.15, m);
  constexpr double kExactTol = 1e-9;
  const auto check = sb::fingerprint_check("lens_distortion", bent, presses, presses);
  INFO(check->verdict);
  REQUIRE(check->consistent);
  CHECK(check->beyond_model_form);
  CHECK(check->acceptance == sb::FingerprintCheck::Acceptance::kEvidence);
  CHECK(std::abs(check->calibration + 0.15) < kExactTol);
  CHECK(check->validation == check->calibration);
  CHECK(check->band.empty());
  REQUIRE(check->held.size() == 2);
  CHECK(check->held[0].first == "k1");
  CHECK(check->held[0].second == check->calibration);
  CHECK(check->held[1] == std::pair<std::string, double>("k2", 0.0));
  CHECK(check->evidence.find("rest grid") != std::string::npos);

  SECTION("a small lens within its noise is not found") {
    // k1 = 0.001 with 0.05 px noise on the rest grid: its standard error is 0.00035 (test_rest_grid_lens), so
    // the estimate is below both min_k1 (0.02) and 3 standard errors' worth of a finding.
    sb::Sensor faint = sb::make_default_sensor();
    std::vector<std::vector<Vec2>> rest{faint.markers_rest_px};
    for (Vec2& m : rest[0]) m = sb::lens_distort_px(faint.camera, 0.001, m);
    add_noise(&rest, 0.05, 99);
    faint.markers_rest_px = rest[0];
    const auto c = sb::fingerprint_check("lens_distortion", faint, presses, presses);
    INFO(c->verdict);
    CHECK_FALSE(c->consistent);
    CHECK(std::abs(c->calibration - 0.001) < 0.002);
  }
}

// ------------------------------------------------------------------------------------- subsurface

namespace {

// A field with fine structure on the grid: two sharp bumps (peak at 0.9 pitch) that grow over 10 frames.
FingerprintSample sharp_field() {
  FingerprintSample s;
  const auto& m = sensor().markers_rest_px;
  for (int k = 1; k <= 10; ++k) {
    std::vector<Vec2> f(m.size());
    for (std::size_t j = 0; j < m.size(); ++j) {
      f[j] = Vec2::Zero();
      for (const auto& [c, dir] :
           {std::pair{Vec2(126.5, 86.5), Vec2(1.0, 0.3)}, {Vec2(225.5, 152.5), Vec2(-0.4, 1.0)}}) {
        const double sc = (m[j] - c).norm() / 30.0;
        f[j] += 4.0 * k / 10.0 * std::exp(-0.5 * sc * sc) * dir;
      }
    }
    s.meas_px.push_back(f);
    s.pred_px.push_back(f);
    s.in_contact.push_back(1);
    s.held.push_back(0);
  }
  return s;
}

}  // namespace

TEST_CASE("subsurface fingerprint: depth from the fine-scale content against the model's", "[fingerprints]") {
  // The grid Laplacian by hand: one marker of an interior 4-neighbourhood moved by (1, 0), the rest still:
  // that marker contributes |0 - 1|^2 = 1 and each of its 4 interior neighbours |1/4 - 0|^2 = 1/16 (marker 31 is
  // the middle of the 7 x 9 grid, its neighbours 22, 30, 32, 40 are all interior).
  std::vector<Vec2> one(sensor().markers_rest_px.size(), Vec2::Zero());
  one[31] = Vec2(1, 0);
  CHECK(sb::grid_laplacian_energy(sensor(), one) == Approx(1.0 + 4.0 / 16.0));

  // Markers 1 mm deep (the effect: Gaussian smoothing, sigma 1 mm over a 2.09 mm pitch), exact model: the
  // Laplacians match exactly at 1 mm, so the depth comes back to the search's resolution (golden section to
  // 1e-7 m after a 0.1 mm scan); 2 % leaves room for a flat minimum.
  constexpr double kExactModelTol = 0.02;
  FingerprintSample s = sharp_field();
  s.meas_px = apply_effect("subsurface_markers", {{"depth_m", 0.001}}, s.meas_px, 0.02);
  const auto exact = sb::subsurface_fingerprint(sensor(), {s});
  INFO("depth " << exact.depth_m);
  CHECK(std::abs(exact.depth_m - 0.001) < kExactModelTol * 0.001);
  CHECK(exact.measured_fine_fraction < exact.model_fine_fraction);

  SECTION("not fooled by a smooth model-form error or a gain") {
    // The model is 30 % too strong (the match is up to a gain: attenuation and the model's stiffness drop
    // out) and wrong by a broad 1 px bump concentrated on the contact (sigma 4 mm = 63 px). The bump is not
    // free of fine-scale content on a 2.09 mm grid (its Laplacian over one pitch is ~ (33/63)^2 ~ 27 % of
    // its height), which reads as shallower markers: without noise the depth comes back at 0.912 mm
    // (-8.8 %); the 0.05 px noise spreads it by +-4 % (30 seeds: 0.874 .. 0.953 mm). Depth within 15 %.
    constexpr double kModelErrorTol = 0.15;
    FingerprintSample w = s;
    const auto& m = sensor().markers_rest_px;
    for (std::size_t k = 0; k < w.pred_px.size(); ++k)
      for (std::size_t j = 0; j < m.size(); ++j) {
        const double sc = (m[j] - Vec2(126.5, 86.5)).norm() / 63.0;
        w.pred_px[k][j] = 1.3 * w.pred_px[k][j] + (k + 1) / 10.0 * std::exp(-0.5 * sc * sc) * Vec2(1.0, 0.0);
      }
    add_noise(&w.meas_px, 0.05, 11);
    const auto f = sb::subsurface_fingerprint(sensor(), {w});
    INFO("depth " << f.depth_m);
    CHECK(std::abs(f.depth_m - 0.001) < kModelErrorTol * 0.001);
  }

  SECTION("markers on the surface: no depth") {
    const FingerprintSample surface = sharp_field();
    const auto f = sb::subsurface_fingerprint(sensor(), {surface});
    CHECK(f.depth_m < 0.25 * 2.0922e-3);  // below a quarter pitch: the finding's floor
    CHECK_FALSE(sb::fingerprint_check("subsurface_markers", sensor(), {surface}, {surface})->consistent);
  }
}

TEST_CASE("tracker noise from the measured series alone", "[fingerprints]") {
  // Markers on a straight ramp in time (x_k = 0.3 k px, y_k = -0.1 k px): the second difference
  // x_{k+1} - 2 x_k + x_{k-1} of the motion is exactly 0, so all of it is noise, N(0, 6 sigma^2); the
  // median of its |.| over 0.6745 sqrt(6) gives sigma back. 20 frames x 63 markers x 2 = 2268 values: the
  // median's relative standard error is about 1.25 / sqrt(2268) = 2.6 %; within 10 %.
  constexpr double kSigma = 0.05, kNoiseTol = 0.10;
  const std::size_t M = sensor().markers_rest_px.size();
  FingerprintSample s;
  for (int k = 0; k < 20; ++k) s.meas_px.emplace_back(M, Vec2(0.3 * k, -0.1 * k));
  const FingerprintSample clean = s;
  add_noise(&s.meas_px, kSigma, 5);
  CHECK(sb::tracker_noise_px({s}) == Approx(kSigma).epsilon(kNoiseTol));
  CHECK(sb::tracker_noise_px({clean}) == Approx(0.0).margin(1e-12));

  SECTION("a slip jump and lost markers do not move it") {
    // Every marker jumps 3 px along x between frames 9 and 10 (a slip): 2 of each marker's 36 second
    // differences carry +-3 px. With 5.6 % of the values outliers, the median of |.| moves to the
    // 0.5 / 0.944 = 53rd percentile of the noise's: Phi^-1(0.765) = 0.722 against 0.6745, +7 %. Within 20 %.
    // A lost marker (NaN) is skipped.
    constexpr double kJumpTol = 0.20;
    FingerprintSample j = s;
    for (int k = 10; k < 20; ++k)
      for (auto& d : j.meas_px[static_cast<std::size_t>(k)]) d += Vec2(3.0, 0.0);
    j.meas_px[4][7] = Vec2(std::nan(""), std::nan(""));
    CHECK(sb::tracker_noise_px({j}) == Approx(kSigma).epsilon(kJumpTol));
  }
  CHECK(std::isnan(sb::tracker_noise_px({})));
}

TEST_CASE("subsurface fingerprint: a depth counts only where the model explains the grid scale to noise",
          "[fingerprints]") {
  // Markers 1 mm deep seen through the exact model, with 0.05 px tracker noise: the smoothed model leaves
  // only the noise at the grid scale (misfit / noise ~ 1, rule <= 4), so the depth is found on both splits.
  FingerprintSample s = sharp_field();
  s.meas_px = apply_effect("subsurface_markers", {{"depth_m", 0.001}}, s.meas_px, 0.02);
  FingerprintSample cal = s, val = s;
  add_noise(&cal.meas_px, 0.05, 21);
  add_noise(&val.meas_px, 0.05, 22);
  const auto exact = sb::fingerprint_check("subsurface_markers", sensor(), {cal}, {val});
  INFO(exact->verdict);
  CHECK(exact->consistent);
  CHECK(exact->calibration == Approx(0.001).epsilon(0.15));

  // The same model against a gel with a feature at the grid scale that the model lacks (as a stick zone's
  // edge would be): a bump of sigma 1 mm (16 px) on the middle marker (31) of the measurement, growing to 3 px
  // at the last frame (the field peaks at 4 px). Its neighbours, one pitch (33 px) away, see
  // exp(-33^2 / 2 / 16^2) = 0.12 of it: its grid Laplacian energy is about 0.86 x 9 = 7.7 px^2 at the last
  // frame and 7.7 x 3.85 = 30 px^2 over the ramp (sum of ((k + 1) / 10)^2), against the noise's
  // 0.05^2 x 787.5 (components x (1 + 1/4)) = 2.0 px^2: 15x once a depth has taken what it can (rule 4x).
  // A model sharper than the gel is the other way round: smoothing it removes its error too, which is why that
  // case reads as depth at all. The depth read here is still right (1.02 mm); the check declines it because
  // nothing says the model's form is right, and the report says why.
  const auto& m = sensor().markers_rest_px;
  for (auto* w : {&cal, &val})
    for (std::size_t k = 0; k < w->meas_px.size(); ++k)
      for (std::size_t j = 0; j < m.size(); ++j) {
        const double sc = (m[j] - m[31]).norm() / 16.0;
        w->meas_px[k][j] += 3.0 * (k + 1) / 10.0 * std::exp(-0.5 * sc * sc) * Vec2(0.0, 1.0);
      }
  const auto wrong = sb::fingerprint_check("subsurface_markers", sensor(), {cal}, {val});
  INFO(wrong->verdict);
  CHECK_FALSE(wrong->consistent);
  CHECK(wrong->verdict.find("wrong at the grid scale") != std::string::npos);

  SECTION("single frames (a photo per sample) give no noise to judge by") {
    // The FOTS press/shear pair has one frame per sample: no second difference in time, no noise estimate,
    // and a depth read against the model cannot be told from its form.
    FingerprintSample one = s;
    one.meas_px = {s.meas_px.back()};
    one.pred_px = {s.pred_px.back()};
    one.in_contact = {1};
    one.held = {0};
    const auto single = sb::fingerprint_check("subsurface_markers", sensor(), {one}, {one});
    INFO(single->verdict);
    CHECK_FALSE(single->consistent);
    CHECK(single->verdict.find("no tracker noise") != std::string::npos);
  }
}

// The registry is keyed by catalogue ids: a key that names no effect (a typo) would never be asked for.
TEST_CASE("every fingerprint in the registry belongs to a catalogued effect", "[fingerprint]") {
  const std::vector<std::string>& catalogue = sb::effect_ids();
  const std::vector<std::string> keys = sb::fingerprinted_effects();
  CHECK(keys == std::vector<std::string>{"viscoelastic_creep", "lens_distortion", "subsurface_markers"});
  for (const std::string& id : keys) {
    INFO(id);
    CHECK(std::find(catalogue.begin(), catalogue.end(), id) != catalogue.end());
    CHECK(sb::has_fingerprint(id));
  }
  CHECK_FALSE(sb::has_fingerprint("dome_sway"));
  CHECK_FALSE(sb::fingerprint_needs_model("dome_sway", sensor()));
  CHECK_FALSE(sb::fingerprint_check("dome_sway", sensor(), {}, {}).has_value());
}

}  // namespace test_fingerprints
