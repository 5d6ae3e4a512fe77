// The bounded Levenberg-Marquardt minimiser on problems whose answers are derived by hand below: where the box
// binds, where it does not, what a step costs in evaluations, and a cancel.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/calibration/bounded_lm.hpp"

namespace {

using sb::BoundedLmOptions;
using sb::BoundedLmProblem;
using sb::LmTermination;

// Solutions are exact in closed form; the minimiser stops at a relative cost change of 1e-12 here.
constexpr double kSolutionTol = 1e-6;
constexpr double kInf = std::numeric_limits<double>::infinity();

// A problem from a residual function, with finite-difference-free analytic Jacobians, counting calls.
struct Counted {
  BoundedLmProblem problem;
  int residual_calls = 0, jacobian_calls = 0;
};

// r(x) = (x1 + x2 - 2, x1 - x2): unbounded optimum (1, 1) with zero cost.
// With x1 <= 0.5 binding: minimise (x2 - 1.5)^2 + (0.5 - x2)^2 over x2:
//   d/dx2 = 2 (x2 - 1.5) - 2 (0.5 - x2) = 4 x2 - 4 = 0  ->  x2 = 1, the optimum (0.5, 1),
//   cost 1/2 ((-0.5)^2 + (-0.5)^2) = 0.25.
void coupled(Counted* c, double x1_hi) {
  c->problem.lo = {-kInf, -kInf};
  c->problem.hi = {x1_hi, kInf};
  c->problem.num_residuals = 2;
  c->problem.residuals = [c](const std::vector<double>& x, std::vector<double>* r) {
    ++c->residual_calls;
    *r = {x[0] + x[1] - 2, x[0] - x[1]};
    return true;
  };
  c->problem.jacobian = [c](const std::vector<double>&, const std::vector<double>&, std::vector<double>* J) {
    ++c->jacobian_calls;
    *J = {1, 1, 1, -1};
    return true;
  };
}

BoundedLmOptions tight() {
  BoundedLmOptions o;
  o.function_tolerance = 1e-12;
  o.max_iterations = 100;
  return o;
}

}  // namespace

TEST_CASE("bounded LM: a linear problem inside the box is Gauss-Newton's answer", "[bounded_lm]") {
  Counted c;
  coupled(&c, kInf);
  const auto res = sb::minimize_bounded_lm(c.problem, {5, -3}, tight());
  CHECK(res.termination == LmTermination::kConvergence);
  CHECK(res.x[0] == Approx(1).margin(kSolutionTol));
  CHECK(res.x[1] == Approx(1).margin(kSolutionTol));
  CHECK(res.cost == Approx(0).margin(kSolutionTol));
}

TEST_CASE("bounded LM: a binding bound is held and the rest solved on it", "[bounded_lm]") {
  Counted c;
  coupled(&c, 0.5);  // the optimum derived above: (0.5, 1), cost 0.25
  const auto res = sb::minimize_bounded_lm(c.problem, {-2, 4}, tight());
  CHECK(res.x[0] == 0.5);  // exactly on the bound: projected, never past it
  CHECK(res.x[1] == Approx(1).margin(kSolutionTol));
  CHECK(res.cost == Approx(0.25).margin(kSolutionTol));
}

TEST_CASE("bounded LM: a start outside the box is projected onto it", "[bounded_lm]") {
  Counted c;
  coupled(&c, 0.5);
  const auto res = sb::minimize_bounded_lm(c.problem, {7, 4}, tight());
  CHECK(res.x[0] == 0.5);
  CHECK(res.x[1] == Approx(1).margin(kSolutionTol));
}

TEST_CASE("bounded LM: a trial step costs one evaluation, an accepted one a Jacobian", "[bounded_lm]") {
  // Every iteration evaluates its trial point once; a Jacobian follows the start and each accepted step but the
  // last (the loop may end there), and none is asked twice at one point: residual calls = 1 + iterations,
  // accepted <= Jacobian calls <= 1 + accepted.
  Counted c;
  coupled(&c, 0.5);
  const auto res = sb::minimize_bounded_lm(c.problem, {-2, 4}, tight());
  CHECK(c.residual_calls == 1 + res.iterations);
  CHECK(c.jacobian_calls <= 1 + res.accepted);
  CHECK(c.jacobian_calls >= std::max(res.accepted, 1));
}

TEST_CASE("bounded LM: Rosenbrock's valley with its minimum outside the box", "[bounded_lm]") {
  // r = (10 (x2 - x1^2), 1 - x1): minimum (1, 1) unbounded. With x1 <= 0.5 the best point has x2 = x1^2
  // (the first residual zero) and x1 as large as allowed: (0.5, 0.25), cost 1/2 (1 - 0.5)^2 = 0.125.
  BoundedLmProblem pr;
  pr.lo = {-2, -2};
  pr.hi = {0.5, 2};
  pr.num_residuals = 2;
  pr.residuals = [](const std::vector<double>& x, std::vector<double>* r) {
    *r = {10 * (x[1] - x[0] * x[0]), 1 - x[0]};
    return true;
  };
  pr.jacobian = [](const std::vector<double>& x, const std::vector<double>&, std::vector<double>* J) {
    *J = {-20 * x[0], 10, -1, 0};
    return true;
  };
  const auto bounded = sb::minimize_bounded_lm(pr, {-1.2, 1}, tight());
  CHECK(bounded.x[0] == 0.5);
  CHECK(bounded.x[1] == Approx(0.25).margin(kSolutionTol));
  CHECK(bounded.cost == Approx(0.125).margin(kSolutionTol));
  pr.hi = {2, 2};
  const auto free = sb::minimize_bounded_lm(pr, {-1.2, 1}, tight());
  CHECK(free.x[0] == Approx(1).margin(kSolutionTol));
  CHECK(free.x[1] == Approx(1).margin(kSolutionTol));
}

TEST_CASE("bounded LM: a variable's step is capped where the problem says so", "[bounded_lm]") {
  // r(x) = x - 10 from x = 0 with steps capped at 1: Gauss-Newton's step (10) is cut to the cap, and the model
  // is exact, so the step is accepted (cost 50 -> 40.5, predicted 9.5, ratio 1); a wider region gives the same
  // capped step, so nothing more is tried. One accepted step ends at exactly 1; uncapped it would end at 10.
  BoundedLmProblem pr;
  pr.lo = {-100};
  pr.hi = {100};
  pr.max_step = {1};
  pr.num_residuals = 1;
  int evaluations = 0;
  pr.residuals = [&](const std::vector<double>& x, std::vector<double>* r) {
    ++evaluations;
    *r = {x[0] - 10};
    return true;
  };
  pr.jacobian = [](const std::vector<double>&, const std::vector<double>&, std::vector<double>* J) {
    *J = {1};
    return true;
  };
  BoundedLmOptions o = tight();
  o.max_iterations = 1;
  auto res = sb::minimize_bounded_lm(pr, {0}, o);
  CHECK(res.x[0] == 1);
  CHECK(res.cost == 40.5);
  CHECK(evaluations == 2);
  o.max_iterations = 100;
  res = sb::minimize_bounded_lm(pr, {0}, o);
  CHECK(res.x[0] == Approx(10).margin(kSolutionTol));
  CHECK(res.accepted >= 10);  // ten steps of at most 1
}

TEST_CASE("bounded LM: the iteration cap and a cancel", "[bounded_lm]") {
  Counted c;
  coupled(&c, 0.5);
  BoundedLmOptions o = tight();
  o.max_iterations = 0;  // the start's cost only: no Jacobian is paid
  auto res = sb::minimize_bounded_lm(c.problem, {-2, 4}, o);
  CHECK(res.termination == LmTermination::kNoConvergence);
  CHECK(c.jacobian_calls == 0);
  CHECK(res.x == std::vector<double>{-2, 4});
  o.max_iterations = 100;
  o.on_iteration = [](int iteration, double) { return iteration < 1; };  // cancel after the first step
  res = sb::minimize_bounded_lm(c.problem, {-2, 4}, o);
  CHECK(res.termination == LmTermination::kAborted);
  CHECK(res.iterations == 1);
  CHECK(sb::to_string(res.termination) == "USER_FAILURE");
}

TEST_CASE("bounded LM: malformed bounds are refused", "[bounded_lm]") {
  Counted c;
  coupled(&c, 0.5);
  c.problem.lo = {1, 0};
  c.problem.hi = {0, 1};
  CHECK_THROWS_WITH(sb::minimize_bounded_lm(c.problem, {0, 0}, tight()), Catch::Contains("lo > hi"));
}
