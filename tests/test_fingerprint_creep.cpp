// The creep fingerprint (core/loop/fingerprint_creep.hpp): tau and c from the change of a field while held
// and after release, through noise.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "core/loop/fingerprints.hpp"
#include "tests/fingerprint_series.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_fingerprint_creep {

using fingerprint_series::add_noise;
using fingerprint_series::apply_effect;
using fingerprint_series::sensor;
using fingerprint_series::Series;
using sb::FingerprintSample;
using sb::Vec2;

namespace {

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

}  // namespace test_fingerprint_creep
