#include "core/workbench/timeline_plot.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_timeline_plot {

using sb::TimelinePlot;

// A plot 200 px wide from x = 100, 80 px high from y = 20, 10 steps of 0.1 s, RMSE 0..4 px. Each step's
// column is 200 / 10 = 20 px wide; step k's middle is 100 + 20 k + 10.
TimelinePlot plot() {
  TimelinePlot p;
  p.left = 100, p.top = 20, p.width = 200, p.height = 80;
  p.num_steps = 10, p.dt_s = 0.1, p.y_max_px = 4;
  return p;
}

TEST_CASE("a step is drawn at its column's middle, a value from the bottom edge", "[timeline_plot]") {
  const auto p = plot();
  CHECK(p.x_of_step(0) == Approx(110));
  CHECK(p.x_of_step(9) == Approx(290));
  CHECK(p.y_of_value(0) == Approx(100));  // the bottom edge: top + height
  CHECK(p.y_of_value(4) == Approx(20));   // y_max at the top
  CHECK(p.y_of_value(1) == Approx(80));   // a quarter of 80 px up
  CHECK(p.y_of_value(9) == Approx(20));   // over the top: clamped
  CHECK(p.y_of_value(-1) == Approx(100));
}

TEST_CASE("a pointer x seeks to the step whose column holds it, clamped at the edges", "[timeline_plot]") {
  const auto p = plot();
  CHECK(p.step_at(100) == 0);
  CHECK(p.step_at(119.9f) == 0);
  CHECK(p.step_at(120) == 1);
  CHECK(p.step_at(205) == 5);  // (205 - 100) / 20 = 5.25
  CHECK(p.step_at(299) == 9);
  CHECK(p.step_at(40) == 0);   // dragged past the left edge
  CHECK(p.step_at(900) == 9);  // past the right edge
  for (int k = 0; k < 10; ++k) CHECK(p.step_at(p.x_of_step(k)) == k);
}

TEST_CASE("ticks are 1, 2 or 5 times a power of ten", "[timeline_plot]") {
  CHECK(sb::nice_tick_step(0.9, 5) == Approx(0.2));  // 0.18 -> 0.2
  CHECK(sb::nice_tick_step(10, 5) == Approx(2));
  CHECK(sb::nice_tick_step(37, 4) == Approx(10));  // 9.25 -> 10
  CHECK(sb::nice_tick_step(0.03, 3) == Approx(0.01));
  CHECK(sb::nice_axis_max(3.3, 4) == Approx(4));    // step 1: up to 4
  CHECK(sb::nice_axis_max(184, 4) == Approx(200));  // step 50: 200
  CHECK(sb::nice_axis_max(0, 4) == Approx(1));
  CHECK(sb::nice_axis_max(std::numeric_limits<double>::quiet_NaN(), 4) == Approx(1));
}

TEST_CASE("the time axis is labelled in seconds at the steps' x", "[timeline_plot]") {
  const auto p = plot();  // steps 0..9: t = 0 .. 0.9 s; 0.9 / 4 = 0.225 -> 0.5 s
  const auto t = p.time_ticks(4);
  REQUIRE(t.size() == 2);
  CHECK(t[0].value == Approx(0));
  CHECK(t[0].px == Approx(110));
  CHECK(t[1].value == Approx(0.5));
  CHECK(t[1].px == Approx(p.x_of_step(5)));  // 0.5 s is step 5: 210 px
  CHECK(t[1].px == Approx(210));
  const auto r = p.rmse_ticks(4);  // 0..4 px, step 1: five ticks, 20 px apart
  REQUIRE(r.size() == 5);
  CHECK(r[2].value == Approx(2));
  CHECK(r[2].px == Approx(60));
}

TEST_CASE("the CSV has a column per model and empty cells where a frame does not count", "[timeline_plot]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::string csv = sb::timeline_csv({"FOTS", "HydroShear"}, {{1.5, nan, 2}, {0.25, 0.5}}, 0.02);
  CHECK(csv ==
        "step,time_s,FOTS,HydroShear\n"
        "0,0,1.5,0.25\n"
        "1,0.02,,0.5\n"
        "2,0.04,2,\n");
}

}  // namespace test_timeline_plot
