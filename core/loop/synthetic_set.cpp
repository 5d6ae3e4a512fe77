#include "core/loop/synthetic_set.hpp"

#include <tbb/parallel_for.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "core/models/bench_workload.hpp"

namespace sb {

namespace {

// A Gaussian stream of its own per (seed, sample, purpose): the set does not depend on the thread schedule.
std::mt19937_64 synthetic_stream(const SyntheticSetOptions& o, std::size_t k, std::uint64_t purpose) {
  return std::mt19937_64(splitmix64(o.seed * 0x9E3779B97F4A7C15ull + 4 * static_cast<std::uint64_t>(k) + purpose));
}

// The model's field for every frame of `s` (NaN where a frame is unmeasured: simulate_sample).
std::vector<std::vector<Vec2>> model_field(const SampleModelFactory& make, const ParamSet& params, const FitSample& s,
                                           std::size_t index) {
  auto model = make(s, index);
  model->set_params(params);
  return simulate_sample(*model, s);
}

}  // namespace

Pose synthetic_jitter(const SyntheticSetOptions& o, std::size_t k, std::size_t n_source) {
  if (k < n_source) return Pose::Identity();
  std::mt19937_64 rng = synthetic_stream(o, k, 0);
  std::normal_distribution<double> shift(0.0, o.shift_m), turn(0.0, o.turn_rad);
  const Vec3 t(shift(rng), shift(rng), shift(rng));
  const Vec3 w(turn(rng), turn(rng), turn(rng));
  Pose J = Pose::Identity();
  if (w.norm() > 0) J.linear() = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
  J.translation() = t;
  return J;
}

std::vector<FitSample> synthetic_samples(const std::vector<FitSample>& source, const SampleModelFactory& make,
                                         const ParamSet& params, const SyntheticSetOptions& o) {
  if (source.empty()) throw std::invalid_argument("synthetic set: no source samples");
  if (o.samples < source.size())
    throw std::invalid_argument("synthetic set: " + std::to_string(o.samples) + " samples is fewer than the source's " +
                                std::to_string(source.size()));
  const std::size_t n = source.size();
  std::vector<std::vector<std::vector<Vec2>>> residual(n);  // [source][frame][marker]: measured - model
  if (o.keep_residual)
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
      residual[i] = model_field(make, params, source[i], i);
      for (std::size_t f = 0; f < residual[i].size(); ++f)
        for (std::size_t m = 0; m < residual[i][f].size(); ++m)
          residual[i][f][m] = source[i].meas_px[f][m] - residual[i][f][m];
    });
  std::vector<FitSample> out(o.samples);
  tbb::parallel_for(std::size_t{0}, o.samples, [&](std::size_t k) {
    const FitSample& src = source[k % n];
    FitSample s = src;
    if (k >= n) s.id = src.id + "~" + std::to_string(k / n);
    const Pose J_E = synthetic_jitter(o, k, n);
    for (Pose& X_EI : s.X_EI) X_EI = J_E * X_EI;
    const auto pred = model_field(make, params, s, k);
    std::mt19937_64 rng = synthetic_stream(o, k, 1);
    std::normal_distribution<double> noise(0.0, o.noise_px);
    for (std::size_t f = 0; f < s.meas_px.size(); ++f)
      for (std::size_t m = 0; m < s.meas_px[f].size(); ++m) {
        Vec2& meas = s.meas_px[f][m];
        if (!meas.allFinite()) continue;
        const Vec2 structure = o.keep_residual ? residual[k % n][f][m] : Vec2::Zero();
        // A frame the model steps without a field (NaN) cannot hold a measurement: keep the source's.
        if (!pred[f][m].allFinite()) continue;
        const double du = noise(rng), dv = noise(rng);
        meas = pred[f][m] + structure + Vec2(du, dv);
      }
    out[k] = std::move(s);
  });
  return out;
}

}  // namespace sb
