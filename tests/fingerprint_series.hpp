#pragma once
// Synthetic marker series for the fingerprint tests (tests/test_fingerprint_{creep,lens,subsurface}.cpp): the
// default sensor, an effect run over a series, tracker noise.
#include <cstdint>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "core/effects/effects.hpp"
#include "core/loop/fingerprints.hpp"

namespace fingerprint_series {

using sb::Vec2;

using Series = std::vector<std::vector<Vec2>>;  // [frame][marker]

inline const sb::Sensor& sensor() {
  static const sb::Sensor s = sb::make_default_sensor();  // 7 x 9 markers at 33 px = 2.09 mm
  return s;
}

// Runs `effect` at `params` over a series frame by frame (as the effect wraps a model).
inline Series apply_effect(const std::string& effect, const std::map<std::string, double>& params, const Series& in,
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

inline void add_noise(Series* s, double sigma, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0.0, sigma);
  for (auto& f : *s)
    for (auto& d : f) {
      const double dx = n(rng);  // two statements: argument order is unspecified (gcc and clang differ)
      d += Vec2(dx, n(rng));
    }
}

}  // namespace fingerprint_series
