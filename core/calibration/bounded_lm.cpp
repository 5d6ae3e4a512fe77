// Projected Levenberg-Marquardt with an active set (see bounded_lm.hpp).
#include "core/calibration/bounded_lm.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

namespace sb {

namespace {

// MINPACK's lmder constants (Moré 1978): the trust region's start (a factor of |D x0|), the accepted step's
// ratio, the band a solved step may miss the radius by, and the largest and smallest shrink on a failure.
constexpr double kRadiusFactor = 100;
constexpr double kMinRatio = 1e-3;  // Ceres's min_relative_decrease
constexpr double kRadiusBand = 0.1;
constexpr double kShrinkMax = 0.5, kShrinkMin = 0.1;
constexpr double kMinDiagonal = 1e-6;  // Ceres's min_lm_diagonal: a column that does nothing still gets a scale
constexpr double kMinRadius = 1e-30;
constexpr int kMuSearchSteps = 200;
// Each failure shrinks the region at least twofold: this many in a row means the model sees nothing to take.
constexpr int kMaxFailuresInARow = 30;

using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

double half_squared_norm(const std::vector<double>& r) {
  double c = 0;
  for (double v : r) c += v * v;
  return 0.5 * c;
}

// The local model at x: 1/2 |r + J d|^2 = f + g.d + 1/2 d.A d with A = J^T J, g = J^T r.
struct LocalModel {
  Eigen::MatrixXd A;
  Eigen::VectorXd g;

  LocalModel(const std::vector<double>& J, const std::vector<double>& r, int P) {
    const auto m = static_cast<Eigen::Index>(r.size());
    const Eigen::Map<const RowMajor> Jm(J.data(), m, P);
    const Eigen::Map<const Eigen::VectorXd> rm(r.data(), m);
    A = Eigen::MatrixXd::Zero(P, P);
    A.selfadjointView<Eigen::Lower>().rankUpdate(Jm.transpose());
    A = A.selfadjointView<Eigen::Lower>();
    g = Jm.transpose() * rm;
  }
  // The predicted decrease f - m(d) of a step d.
  double predicted_decrease(const Eigen::VectorXd& d) const { return -(g.dot(d) + 0.5 * d.dot(A * d)); }
};

// A variable at a bound whose descent direction -g leaves the box stays there this step.
std::vector<int> free_variables(const std::vector<double>& x, const BoundedLmProblem& pr, const Eigen::VectorXd& g) {
  std::vector<int> free;
  for (int k = 0; k < static_cast<int>(x.size()); ++k) {
    const bool held = (x[k] <= pr.lo[k] && g[k] > 0) || (x[k] >= pr.hi[k] && g[k] < 0);
    if (!held) free.push_back(k);
  }
  return free;
}

// max_k |x_k - clamp(x_k - g_k)|: zero exactly at a bounded stationary point (Ceres's gradient test with bounds).
double projected_gradient_norm(const std::vector<double>& x, const BoundedLmProblem& pr, const Eigen::VectorXd& g) {
  double n = 0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    const auto i = static_cast<Eigen::Index>(k);
    n = std::max(n, std::abs(x[k] - std::clamp(x[k] - g[i], pr.lo[k], pr.hi[k])));
  }
  return n;
}

double scaled_norm(const Eigen::VectorXd& d, const Eigen::VectorXd& D) {
  return (D.array() * d.array()).matrix().norm();
}

// The step over the free variables solving (A + mu D^2) d = -g, zero for the held ones.
Eigen::VectorXd lm_step(const LocalModel& lm, const Eigen::VectorXd& D, const std::vector<int>& free, double mu) {
  const auto F = static_cast<Eigen::Index>(free.size());
  Eigen::MatrixXd M(F, F);
  Eigen::VectorXd b(F);
  for (Eigen::Index a = 0; a < F; ++a) {
    for (Eigen::Index c = 0; c < F; ++c) M(a, c) = lm.A(free[a], free[c]);
    M(a, a) += mu * D[free[a]] * D[free[a]];
    b[a] = -lm.g[free[a]];
  }
  const Eigen::VectorXd d_free = M.ldlt().solve(b);
  Eigen::VectorXd d = Eigen::VectorXd::Zero(lm.g.size());
  for (Eigen::Index a = 0; a < F; ++a) d[free[a]] = d_free[a];
  return d;
}

// The Levenberg-Marquardt step inside the trust region |D d| <= radius: Gauss-Newton's (a vanishing mu) when
// it fits, else the mu whose step's length is the radius within the band (bisection in log mu: |D d(mu)| falls
// with mu, and P is small).
Eigen::VectorXd trust_region_step(const LocalModel& lm, const Eigen::VectorXd& D, const std::vector<int>& free,
                                  double radius) {
  double mu_lo = 1e-14, mu_hi = 1e40;
  Eigen::VectorXd d = lm_step(lm, D, free, mu_lo);
  if (scaled_norm(d, D) <= (1 + kRadiusBand) * radius) return d;
  for (int i = 0; i < kMuSearchSteps; ++i) {
    const double mu = std::sqrt(mu_lo * mu_hi);
    d = lm_step(lm, D, free, mu);
    const double n = scaled_norm(d, D);
    if (n > (1 + kRadiusBand) * radius) {
      mu_lo = mu;
    } else if (n < (1 - kRadiusBand) * radius) {
      mu_hi = mu;
    } else {
      break;
    }
  }
  return d;
}

// MINPACK's shrink on a failed step: the minimum along the step of the quadratic through f, the slope g.s and
// f(s), as a fraction of the step, within [0.1, 0.5].
double shrink_factor(double slope, double actual_decrease) {
  if (actual_decrease >= 0) return kShrinkMax;
  const double t = 0.5 * slope / (slope + 0.5 * actual_decrease);
  return std::clamp(t, kShrinkMin, kShrinkMax);
}

std::vector<double> project(const std::vector<double>& x, const Eigen::VectorXd& d, const BoundedLmProblem& pr) {
  std::vector<double> y(x.size());
  for (std::size_t k = 0; k < x.size(); ++k)
    y[k] = std::clamp(x[k] + d[static_cast<Eigen::Index>(k)], pr.lo[k], pr.hi[k]);
  return y;
}

void check(const BoundedLmProblem& pr, const std::vector<double>& x0) {
  if (pr.lo.size() != x0.size() || pr.hi.size() != x0.size())
    throw std::invalid_argument("bounded LM: bounds and start differ in size");
  for (std::size_t k = 0; k < x0.size(); ++k)
    if (!(pr.lo[k] <= pr.hi[k])) throw std::invalid_argument("bounded LM: variable " + std::to_string(k) + " lo > hi");
}

}  // namespace

std::string to_string(LmTermination t) {
  switch (t) {
    case LmTermination::Convergence: return "CONVERGENCE";
    case LmTermination::NoConvergence: return "NO_CONVERGENCE";
    case LmTermination::Aborted: return "USER_FAILURE";
  }
  return "?";
}

BoundedLmResult minimize_bounded_lm(const BoundedLmProblem& pr, std::vector<double> x0, const BoundedLmOptions& o) {
  check(pr, x0);
  const int P = static_cast<int>(x0.size());
  BoundedLmResult res;
  res.x = project(x0, Eigen::VectorXd::Zero(P), pr);
  std::vector<double> r(static_cast<std::size_t>(pr.num_residuals)), r_try(r.size()), J;
  const auto finish = [&](LmTermination t) {
    res.termination = t;
    return res;
  };
  if (!pr.residuals(res.x, &r)) return finish(LmTermination::Aborted);
  res.cost = half_squared_norm(r);
  if (o.on_iteration && !o.on_iteration(0, res.cost)) return finish(LmTermination::Aborted);
  Eigen::VectorXd D = Eigen::VectorXd::Zero(P);  // column scales, never decreasing (MINPACK's mode 1)
  double radius = 0;
  std::unique_ptr<LocalModel> lm;
  int failures_in_a_row = 0;
  while (res.accepted < o.max_iterations && failures_in_a_row < kMaxFailuresInARow) {
    if (!lm) {  // at the start and after an accepted step; a rejected one keeps x and its model
      if (!pr.jacobian(res.x, r, &J)) return finish(LmTermination::Aborted);
      lm = std::make_unique<LocalModel>(J, r, P);
      D = D.cwiseMax(lm->A.diagonal().cwiseMax(kMinDiagonal).cwiseSqrt());
      if (radius == 0) {
        const double xn = scaled_norm(Eigen::Map<const Eigen::VectorXd>(res.x.data(), P), D);
        radius = xn > 0 ? kRadiusFactor * xn : kRadiusFactor;
      }
      if (projected_gradient_norm(res.x, pr, lm->g) <= o.gradient_tolerance) return finish(LmTermination::Convergence);
    }
    const std::vector<double> x_try =
        project(res.x, trust_region_step(*lm, D, free_variables(res.x, pr, lm->g), radius), pr);
    Eigen::VectorXd step(P);
    for (int k = 0; k < P; ++k) step[k] = x_try[k] - res.x[k];
    const double x_norm = Eigen::Map<const Eigen::VectorXd>(res.x.data(), P).norm();
    if (step.norm() <= o.parameter_tolerance * (x_norm + o.parameter_tolerance))
      return finish(LmTermination::Convergence);
    ++res.iterations;
    if (!pr.residuals(x_try, &r_try)) return finish(LmTermination::Aborted);
    const double cost_try = half_squared_norm(r_try);
    const double actual = res.cost - cost_try;
    const double predicted = lm->predicted_decrease(step);
    const double rho = predicted > 0 ? actual / predicted : -1;
    const double step_norm = scaled_norm(step, D);
    const bool accepted = rho > kMinRatio;
    if (rho < 0.25) {
      radius = shrink_factor(lm->g.dot(step), actual) * std::min(radius, step_norm / kShrinkMin);
    } else if (rho > 0.75) {
      radius = std::max(radius, 2 * step_norm);
    }
    // Converged: an accepted step changed the cost by less than the tolerance (Ceres's rule), or the model
    // predicts no more than that inside the region.
    const bool converged = std::abs(actual) <= o.function_tolerance * res.cost &&
                           (accepted || predicted <= o.function_tolerance * res.cost);
    if (accepted) {
      res.x = x_try;
      res.cost = cost_try;
      r.swap(r_try);
      lm.reset();
      ++res.accepted;
      failures_in_a_row = 0;
    } else {
      ++failures_in_a_row;
    }
    if (o.on_iteration && !o.on_iteration(res.iterations, res.cost)) return finish(LmTermination::Aborted);
    if (converged || radius < kMinRadius) return finish(LmTermination::Convergence);
  }
  return finish(failures_in_a_row < kMaxFailuresInARow ? LmTermination::NoConvergence : LmTermination::Convergence);
}

}  // namespace sb
