// Cost of the effect layer per step: a trivial base model (fixed field) wrapped with every effect at
// non-default parameters, on the 7 x 9 GelSight Mini grid and a dense 20 x 20 grid.
#include <benchmark/benchmark.h>

#include <cmath>

#include "core/effects/effects.hpp"

namespace {

constexpr double kIndenterRadius = 0.004;

class FixedField final : public sb::ShearModel {
 public:
  explicit FixedField(std::size_t n) : field_(n, sb::Vec2(1.0, -0.5)) {}
  std::string id() const override { return "fixed"; }
  const sb::ParamSet& params() const override { return params_; }
  void set_params(const sb::ParamSet& p) override { params_ = p; }
  void reset() override {}
  void step(const sb::Pose&, double, sb::FieldOutput* out) override { out->disp_px = field_; }
  std::unique_ptr<sb::ShearModel> clone() const override { return std::make_unique<FixedField>(*this); }

 private:
  std::vector<sb::Vec2> field_;
  sb::ParamSet params_;
};

std::shared_ptr<sb::Sensor> grid_sensor(int rows, int cols, double pitch_m) {
  auto s = std::make_shared<sb::Sensor>();
  s->gel_sdf = sb::make_pad_sdf(s->gel.size_m, s->gel.thickness_m);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const sb::Vec2 p((c - 0.5 * (cols - 1)) * pitch_m, (r - 0.5 * (rows - 1)) * pitch_m);
      s->p_EM.emplace_back(p.x(), p.y(), 0.0);
      s->markers_rest_px.push_back(s->camera.px_from_E(p));
    }
  return s;
}

// A sphere sampled on a Fibonacci lattice at about the HydroShear spacing (0.75 mm): ~360 points.
std::shared_ptr<sb::Indenter> sphere_indenter() {
  auto ind = std::make_shared<sb::Indenter>();
  ind->sdf = sb::make_sphere_sdf(kIndenterRadius);
  const int n = 360;
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / n, rho = std::sqrt(1.0 - z * z), phi = 2.399963229728653 * i;
    ind->samples.p_IS.emplace_back(kIndenterRadius * rho * std::cos(phi), kIndenterRadius * rho * std::sin(phi),
                                   kIndenterRadius * z);
  }
  return ind;
}

void run(benchmark::State& state, bool with_effects, bool wrapper_only = false) {
  const int side = static_cast<int>(state.range(0));
  auto sensor = side == 0 ? grid_sensor(7, 9, 0.0021) : grid_sensor(side, side, 0.001);
  std::unique_ptr<sb::ShearModel> model = std::make_unique<FixedField>(sensor->p_EM.size());
  if (wrapper_only)  // the context alone: penetration of ~360 indenter samples
    model = sb::wrap_with_effects(std::move(model), {}, sensor, sphere_indenter());
  if (with_effects) {
    auto m = sb::wrap_with_effects(std::move(model), sb::effect_ids(), sensor, sphere_indenter());
    sb::ParamSet p = m->params();
    p.set("viscoelastic_creep.creep_fraction", 0.3);
    p.set("lens_distortion.k1", 0.05);
    p.set("subsurface_markers.depth_m", 0.0005);
    p.set("gravity_preload.gx_px", 0.5);
    p.set("edge_constraint.strength", 0.5);
    p.set("load_stiffening.beta_per_m", 100.0);
    p.set("tracker_bias.gain", 0.95);
    p.set("camera_misalignment.rotation_rad", 0.01);
    m->set_params(p);
    model = std::move(m);
  }
  sb::FieldOutput out;
  int k = 0;
  for (auto _ : state) {
    sb::Pose X = sb::Pose::Identity();
    X.translation() = sb::Vec3(0.0, 0.0, kIndenterRadius - 0.001 * (1.0 + std::sin(0.01 * k++)));
    model->step(X, 0.01, &out);
    benchmark::DoNotOptimize(out.disp_px.data());
  }
  state.counters["markers"] = static_cast<double>(sensor->p_EM.size());
}

void BM_BaseOnly(benchmark::State& s) { run(s, false); }
void BM_AllEffects(benchmark::State& s) { run(s, true); }
void BM_WrapperOnly(benchmark::State& s) { run(s, false, true); }

}  // namespace

// Arg 0: the 7 x 9 GelSight Mini grid; Arg 20: a 20 x 20 grid.
BENCHMARK(BM_BaseOnly)->Arg(0)->Arg(20);
BENCHMARK(BM_AllEffects)->Arg(0)->Arg(20);
BENCHMARK(BM_WrapperOnly)->Arg(0)->Arg(20);
