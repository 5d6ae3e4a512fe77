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
  for (int i = 0; i < 400; ++i) {
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
  PoseInputs x;
  x.depth_m = 0.0021, x.tilt = Vec2(0.03, -0.02), x.travel_m = Vec2(-0.001, 0.0013), x.twist_rad = 0.02;
  const auto want = law(x, 3), got = s.predict(x);
  for (int m = 0; m < 3; ++m) CHECK((got[m] - want[m]).norm() < kSolveTol);
  CHECK_THROWS_AS(ResponseSurface::fit(grid, fields, 4), std::invalid_argument);
  fields.pop_back();
  CHECK_THROWS_AS(ResponseSurface::fit(grid, fields, 3), std::invalid_argument);
}

TEST_CASE("analyse_input_response: a model at half the law has gain 2 and no shape error", "[input_response]") {
  // measured = law, model = law / 2: every response's best gain is 2 with nothing left after it; the inputs
  // alone predict validation exactly, the model misses by half the measured RMS.
  const auto grid = input_grid();
  std::vector<ScoredInputFrame> cal, val;
  for (std::size_t i = 0; i < grid.size(); ++i)
    (i % 4 == 0 ? val : cal).push_back({grid[i], law(grid[i], 4), law(grid[i], 4, 0.5)});
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
