// A large set from a small one (core/loop/synthetic_set.hpp), against a model whose field is known by hand: every
// marker moves by (gain * 1000 x_EI, gain * 1000 y_EI) px, the indenter's position in mm.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "core/loop/synthetic_set.hpp"

namespace test_synthetic_set {

using sb::FieldOutput;
using sb::FitSample;
using sb::ParamSet;
using sb::Pose;
using sb::Vec2;
using sb::Vec3;

constexpr std::size_t kMarkers = 3;

ParamSet gain_table() {
  return ParamSet(
      {sb::ParamSpec{.name = "gain", .unit = "", .default_value = 2.0, .min = 0, .max = 10, .help = "px per mm"}});
}

class PositionModel final : public sb::ShearModel {
 public:
  std::string id() const override { return "position"; }
  const ParamSet& params() const override { return params_; }
  void set_params(const ParamSet& p) override { params_ = p; }
  void reset() override {}
  void step(const Pose& X_EI, double /*dt*/, FieldOutput* out) override {
    if (out == nullptr) return;
    const Vec3 p_mm = 1000.0 * X_EI.translation();
    out->disp_px.assign(kMarkers, params_[0] * Vec2(p_mm.x(), p_mm.y()));
  }
  std::unique_ptr<sb::ShearModel> clone() const override { return std::make_unique<PositionModel>(*this); }

 private:
  ParamSet params_ = gain_table();
};

// Two samples of two frames; the second marker of sample 1 unmeasured. Measured = gain 2 field + a known residual.
std::vector<FitSample> source_samples() {
  std::vector<FitSample> out(2);
  for (std::size_t i = 0; i < out.size(); ++i) {
    FitSample& s = out[i];
    s.id = "s" + std::to_string(i);
    s.split = i == 0 ? "calibration" : "validation";
    for (int k = 0; k < 2; ++k) {
      Pose X = Pose::Identity();
      X.translation() = Vec3(1e-3 * (k + 1), -2e-3 * static_cast<double>(i), -1e-3);
      s.X_EI.push_back(X);
      std::vector<Vec2> meas(kMarkers);
      for (std::size_t m = 0; m < kMarkers; ++m)
        meas[m] = 2.0 * Vec2(1.0 * (k + 1), -2.0 * static_cast<double>(i)) + Vec2(0.1 * m, -0.3);
      s.meas_px.push_back(meas);
    }
    if (i == 1) s.meas_px[1][1] = Vec2::Constant(std::numeric_limits<double>::quiet_NaN());
  }
  return out;
}

sb::SampleModelFactory position_factory() {
  return [](const FitSample&, std::size_t) { return std::make_unique<PositionModel>(); };
}

constexpr double kExact = 1e-12;

TEST_CASE("synthetic set: the first copy is the source, later copies carry the field at the jittered path",
          "[synthetic_set]") {
  const auto source = source_samples();
  sb::SyntheticSetOptions o;
  o.samples = 5;  // sources 0, 1, 0, 1, 0
  o.noise_px = 0;
  const auto made = sb::synthetic_samples(source, position_factory(), gain_table(), o);
  REQUIRE(made.size() == 5);
  CHECK(made[0].id == "s0");
  CHECK(made[3].id == "s1~1");
  CHECK(made[4].id == "s0~2");
  CHECK(made[3].split == "validation");
  // k < n: J = I, so meas' = pred + (meas - pred) = meas.
  for (std::size_t i = 0; i < 2; ++i)
    for (std::size_t f = 0; f < 2; ++f)
      for (std::size_t m = 0; m < kMarkers; ++m)
        if (source[i].meas_px[f][m].allFinite())
          CHECK((made[i].meas_px[f][m] - source[i].meas_px[f][m]).norm() < kExact);
  CHECK(!made[1].meas_px[1][1].allFinite());
  CHECK(!made[3].meas_px[1][1].allFinite());  // unmeasured stays unmeasured in every copy
  // k >= n: X' = J X. The field is linear in the position, so meas' - meas = 2000 (p' - p)_xy, p' = J p.
  for (std::size_t k = 2; k < 5; ++k) {
    const Pose J = sb::synthetic_jitter(o, k, 2);
    CHECK(!J.isApprox(Pose::Identity()));
    const FitSample& src = source[k % 2];
    for (std::size_t f = 0; f < 2; ++f) {
      CHECK(made[k].X_EI[f].isApprox(J * src.X_EI[f], kExact));
      const Vec3 dp = made[k].X_EI[f].translation() - src.X_EI[f].translation();
      const Vec2 expected = src.meas_px[f][0] + 2000.0 * Vec2(dp.x(), dp.y());
      CHECK((made[k].meas_px[f][0] - expected).norm() < 1e-9);
    }
  }
}

TEST_CASE("synthetic set: the model's field alone, the noise's size and the jitter's determinism", "[synthetic_set]") {
  const auto source = source_samples();
  sb::SyntheticSetOptions o;
  o.samples = 2;
  o.noise_px = 0;
  o.keep_residual = false;
  // Without the residual the copy of sample 0 frame 0 is the gain-2 field at (1, 0) mm: (2, 0) px.
  const auto model_only = sb::synthetic_samples(source, position_factory(), gain_table(), o);
  CHECK((model_only[0].meas_px[0][2] - Vec2(2.0, 0.0)).norm() < kExact);
  // Noise: 2000 copies of a 3-marker 2-frame sample, 23,994 finite components; their sd within 3 % of 0.5 px.
  o.samples = 4000;
  o.noise_px = 0.5;
  o.shift_m = o.turn_rad = 0;
  const auto noisy = sb::synthetic_samples(source, position_factory(), gain_table(), o);
  double sum_sq = 0;
  double n = 0;
  for (const auto& s : noisy)
    for (std::size_t f = 0; f < 2; ++f)
      for (std::size_t m = 0; m < kMarkers; ++m) {
        const Vec2 pred = 2000.0 * Vec2(s.X_EI[f].translation().x(), s.X_EI[f].translation().y());
        if (!s.meas_px[f][m].allFinite()) continue;
        sum_sq += (s.meas_px[f][m] - pred).squaredNorm();
        n += 2;
      }
  constexpr double kNoiseSdTolerance = 0.03;
  CHECK(std::abs(std::sqrt(sum_sq / n) - 0.5) < kNoiseSdTolerance * 0.5);
  // The jitter depends on (seed, k) only; another seed gives another one.
  sb::SyntheticSetOptions a;
  CHECK(sb::synthetic_jitter(a, 7, 2).isApprox(sb::synthetic_jitter(a, 7, 2)));
  sb::SyntheticSetOptions b = a;
  b.seed = a.seed + 1;
  CHECK(!sb::synthetic_jitter(a, 7, 2).isApprox(sb::synthetic_jitter(b, 7, 2)));
  CHECK_THROWS(sb::synthetic_samples(source, position_factory(), gain_table(), sb::SyntheticSetOptions{.samples = 1}));
}

}  // namespace test_synthetic_set
