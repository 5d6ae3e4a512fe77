#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "core/loop/input_response.hpp"
#include "model_fixtures.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_input_response {

using namespace sb;

namespace {

constexpr double kExact = 1e-12;    // metres and radians: closed-form pose arithmetic
constexpr double kSolveTol = 1e-8;  // px: a least-squares fit of an exact polynomial (conditioning ~1e4)
constexpr double kBox = 0.004;      // box indenter's side: its flat bottom is at z = -2 mm in I

// The box's bottom `depth` into the pad at (x, y), turned by R.
Pose box_at(double x, double y, double depth, const Mat3& R = Mat3::Identity()) {
  Pose X = Pose::Identity();
  X.linear() = R;
  X.translation() = Vec3(x, y, kBox / 2 - depth);
  return X;
}

// A field that is an exact polynomial of the inputs: marker m gets (m + 1) times
// u = 2000 depth + 1000 travel_x + 3e5 depth travel_y, v = 50 twist - 4e8 depth^3 + 5 tilt_x.
std::vector<Vec2> law(const PoseInputs& x, int markers, double scale = 1.0) {
  std::vector<Vec2> f;
  for (int m = 0; m < markers; ++m) {
    const double u = 2000 * x.depth_m + 1000 * x.travel_m.x() + 3e5 * x.depth_m * x.travel_m.y();
    const double v = 50 * x.twist_rad - 4e8 * std::pow(x.depth_m, 3) + 5 * x.tilt.x();
    f.push_back(scale * (m + 1) * Vec2(u, v));
  }
  return f;
}

// Inputs spread over a grid of depths, tilts, travels and twists (deterministic).
std::vector<PoseInputs> input_grid() {
  std::vector<PoseInputs> out;
  for (int i = 0; i < 900; ++i) {  // >= 10 frames per term of a cubic of six inputs (84)
    PoseInputs x;
    x.depth_m = 0.0005 + 0.0005 * (i % 7);
    x.tilt = Vec2(0.1 * std::sin(i * 0.37), 0.1 * std::cos(i * 0.53));
    x.travel_m = Vec2(0.002 * std::sin(i * 1.1), 0.002 * std::cos(i * 0.71));
    x.twist_rad = 0.05 * std::sin(i * 0.29);
    out.push_back(x);
  }
  return out;
}

}  // namespace

TEST_CASE("pose_inputs: depth, tilt, travel and twist since first contact from the poses alone", "[input_response]") {
  // Box bottom 1 mm above the pad (no contact), then 1 mm in at (1, 2) mm, then moved by (0.5, -0.25) mm and
  // twisted 0.1 rad, then tilted 0.2 rad about x. R_x(t) z = (0, -sin t, cos t): tilt (0, -sin 0.2).
  const auto box = sbtest::box_indenter(kBox);
  const auto sensor = sbtest::test_sensor();
  const Mat3 twist = Rz(0.1);
  const Mat3 tilt = Eigen::AngleAxisd(0.2, Vec3::UnitX()).toRotationMatrix();
  const std::vector<Pose> path = {box_at(0.001, 0.002, -0.001), box_at(0.001, 0.002, 0.001),
                                  box_at(0.0015, 0.00175, 0.001, twist), box_at(0.0015, 0.00175, 0.001, tilt)};
  const auto x = pose_inputs(*sensor->gel_sdf, *box, path);
  REQUIRE(x.size() == 4);
  CHECK(x[0].depth_m == 0.0);
  CHECK(x[0].travel_m.norm() == 0.0);
  CHECK(std::abs(x[1].depth_m - 0.001) < kExact);
  CHECK(x[1].travel_m.norm() < kExact);
  CHECK((x[2].travel_m - Vec2(0.0005, -0.00025)).norm() < kExact);
  CHECK(std::abs(x[2].twist_rad - 0.1) < kExact);
  CHECK((x[3].tilt - Vec2(0.0, -std::sin(0.2))).norm() < kExact);
  CHECK(std::abs(x[3].twist_rad) < kExact);
  CHECK_THROWS_AS(pose_inputs(*sensor->gel_sdf, *box, {}), std::invalid_argument);
}

TEST_CASE("ResponseSurface reproduces a cubic law of the inputs away from the fitted points", "[input_response]") {
  const auto grid = input_grid();
  std::vector<std::vector<Vec2>> fields;
  for (const auto& x : grid) fields.push_back(law(x, 3));
  fields[5][1] = Vec2::Constant(std::nan(""));  // a lost marker in one frame is left out of its fit
  const auto s = ResponseSurface::fit(grid, fields, 3);
  CHECK(s.terms() == 84);  // C(6 + 3, 3) monomials of six varying inputs
  CHECK(s.degree() == 3);
  PoseInputs x;
  x.depth_m = 0.0021, x.tilt = Vec2(0.03, -0.02), x.travel_m = Vec2(-0.001, 0.0013), x.twist_rad = 0.02;
  const auto want = law(x, 3), got = s.predict(x);
  for (int m = 0; m < 3; ++m) CHECK((got[m] - want[m]).norm() < kSolveTol);
  // 100 frames: a cubic's 84 terms and a quadratic's 28 want 840 and 280 frames; a linear function's 7 want 70.
  const std::vector<PoseInputs> few(grid.begin(), grid.begin() + 100);
  const std::vector<std::vector<Vec2>> few_fields(fields.begin(), fields.begin() + 100);
  const auto linear = ResponseSurface::fit(few, few_fields, 3);
  CHECK(linear.degree() == 1);
  CHECK(linear.terms() == 7);
  CHECK_THROWS_AS(ResponseSurface::fit(grid, fields, 4), std::invalid_argument);
  fields.pop_back();
  CHECK_THROWS_AS(ResponseSurface::fit(grid, fields, 3), std::invalid_argument);
}

TEST_CASE("analyse_input_response scores the inputs alone only inside the calibration range", "[input_response]") {
  // The grid spans depth 0.5..3.5 mm (0.0005 + 0.0005 * (i % 7)); a frame pressed 10 mm deep lies outside that
  // range, one of the grid's own frames inside. The model is off by 1 px in u on every marker of both frames.
  // Scored: the frame inside alone (2 markers), where the surface is exact (0 px) and the model 1 px off;
  // the deep frame is counted and left out.
  const auto grid = input_grid();
  PoseInputs deep = grid[3];
  deep.depth_m = 0.010;
  std::vector<ScoredInputFrame> cal, val;
  for (const auto& x : grid) cal.push_back({x, law(x, 2), law(x, 2)});
  const auto off_by_one = [](std::vector<Vec2> f) {
    for (auto& d : f) d.x() += 1.0;
    return f;
  };
  val.push_back({grid[10], law(grid[10], 2), off_by_one(law(grid[10], 2))});
  val.push_back({deep, law(deep, 2), off_by_one(law(deep, 2))});
  std::vector<std::vector<Vec2>> fields;
  for (const auto& f : cal) fields.push_back(f.measured_px);
  const auto s = ResponseSurface::fit(grid, fields, 3);
  CHECK(s.within_range(grid[10]));
  CHECK_FALSE(s.within_range(deep));
  const auto a = analyse_input_response(cal, val);
  CHECK(a.validation_frames == 2);
  CHECK(a.validation_frames_outside == 1);
  CHECK(a.validation_marker_frames == 2);
  CHECK(a.inputs_only_rmse_px < kSolveTol);
  CHECK(a.model_rmse_px == Approx(1.0).epsilon(1e-12));
}

TEST_CASE("analyse_input_response: a model at half the law has gain 2 and no shape error", "[input_response]") {
  // measured = law, model = law / 2: every response's best gain is 2 with nothing left after it; the inputs
  // alone predict validation exactly, the model misses by half the measured RMS.
  const auto grid = input_grid();
  std::vector<ScoredInputFrame> cal, val;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    const ScoredInputFrame f{grid[i], law(grid[i], 4), law(grid[i], 4, 0.5)};
    cal.push_back(f);  // every frame: validation inside the calibration range, where the surface is exact
    if (i % 4 == 0) val.push_back(f);
  }
  const auto a = analyse_input_response(cal, val);
  REQUIRE(a.responses.size() == 7);  // the reference and one row per input
  for (const auto& r : a.responses) {
    INFO(r.input);
    if (r.model_rms_px < 1e-6) continue;  // tilt y: the law does not depend on it
    CHECK(r.gain == Approx(2.0).epsilon(1e-6));
    CHECK(r.after_gain_rms_px < 1e-6);
  }
  CHECK(a.inputs_only_rmse_px < kSolveTol);
  double sq = 0;
  long n = 0;
  for (const auto& f : val)
    for (const auto& d : f.measured_px) sq += d.squaredNorm(), ++n;
  CHECK(a.model_rmse_px == Approx(0.5 * std::sqrt(sq / double(n))).epsilon(1e-9));
  CHECK_THROWS_AS(analyse_input_response({}, val), std::invalid_argument);
}

}  // namespace test_input_response
