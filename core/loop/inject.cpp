// Known effects put into measured data (inject.hpp).
#include "core/loop/inject.hpp"

#include "core/effects/effects.hpp"
#include "core/loop/rest_grid_lens.hpp"

namespace sb {

void insert_hold(const Sensor& sensor, int frames, double noise_px, std::mt19937_64* rng, FitSample* s) {
  std::normal_distribution<double> noise(0.0, noise_px);
  std::size_t deepest = 0;
  double depth = -1;
  for (std::size_t k = 0; k < s->X_EI.size(); ++k) {
    const double d = indenter_penetration(*sensor.gel_sdf, *s->indenter, s->X_EI[k]).depth_m;
    if (d > depth) depth = d, deepest = k;
  }
  s->X_EI.insert(s->X_EI.begin() + deepest, frames, s->X_EI[deepest]);
  s->meas_px.insert(s->meas_px.begin() + deepest, frames, s->meas_px[deepest]);
  for (int k = 1; k <= frames; ++k)
    for (auto& d : s->meas_px[deepest + k]) {
      const double du = noise(*rng);  // sequenced: argument order is unspecified
      d += Vec2(du, noise(*rng));
    }
}

void inject_effect(const Sensor& sensor, const std::string& effect, const std::map<std::string, double>& params,
                   FitSample* s) {
  auto e = make_effect(effect);
  ParamSet p = e->params();
  for (const auto& [name, value] : params) p.set(name, value);
  e->set_params(p);
  e->reset();
  EffectContext ctx;
  ctx.sensor = &sensor;
  for (std::size_t k = 0; k < s->meas_px.size(); ++k) {
    ctx.dt_s = k == 0 ? 0.0 : s->dt_s;
    ctx.time_s += ctx.dt_s;
    e->apply(ctx, s->meas_px[k]);
  }
}

std::vector<Vec2> recorded_rest_px(const Camera& camera, const std::string& effect,
                                   const std::map<std::string, double>& params, std::vector<Vec2> rest_px) {
  if (effect != "lens_distortion") return rest_px;
  const auto k1 = params.find("k1");
  if (k1 == params.end()) return rest_px;  // the effect's default k1 is 0: no lens
  for (Vec2& m : rest_px) m = lens_distort_px(camera, k1->second, m);
  return rest_px;
}

}  // namespace sb
