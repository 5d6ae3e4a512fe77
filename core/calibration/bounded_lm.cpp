// Projected Levenberg-Marquardt with an active set (see bounded_lm.hpp).
#include "core/calibration/bounded_lm.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
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
// After a step the model predicted well to the region's edge: up to this many trials from the same model in a
// region this many times wider.
constexpr int kMaxExpansions = 3;
constexpr double kExpansion = 4;
constexpr double kMinWidening = 1.5;  // a wider region's step shorter than this (x the last) is not tried
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

// Where the step is taken from: the point, the box, and the local model with its column scales.
struct StepContext {
  const std::vector<double>& x;
  const BoundedLmProblem& pr;
  const LocalModel& lm;
  const Eigen::VectorXd& D;
  std::vector<int> free;  // free_variables(x)
  // This step's box: the bounds, narrowed to x -+ max_step where the problem caps a variable's step.
  std::vector<double> lo, hi;

  StepContext(const std::vector<double>& x_, const BoundedLmProblem& pr_, const LocalModel& lm_,
              const Eigen::VectorXd& D_)
      : x(x_), pr(pr_), lm(lm_), D(D_), free(free_variables(x_, pr_, lm_.g)), lo(pr_.lo), hi(pr_.hi) {
    for (std::size_t k = 0; k < pr.max_step.size() && k < x.size(); ++k) {
      lo[k] = std::max(lo[k], x[k] - pr.max_step[k]);
      hi[k] = std::min(hi[k], x[k] + pr.max_step[k]);
    }
  }
};

// The step minimising the regularised model 1/2 d.(A + mu D^2) d + g.d inside the step's box: solved over the free
// variables; a variable the solution takes past its bound is put on the bound and the rest solved again with it
// there (at most P times). Without the re-solve, clamping alone can leave a step the model calls an ascent.
Eigen::VectorXd lm_step(const StepContext& c, double mu) {
  const Eigen::Index P = c.lm.g.size();
  Eigen::VectorXd d = Eigen::VectorXd::Zero(P);
  std::vector<int> free = c.free;
  for (Eigen::Index pass = 0; pass <= P && !free.empty(); ++pass) {
    const auto F = static_cast<Eigen::Index>(free.size());
    Eigen::MatrixXd M(F, F);
    Eigen::VectorXd b(F);
    for (Eigen::Index a = 0; a < F; ++a) {
      for (Eigen::Index k = 0; k < F; ++k) M(a, k) = c.lm.A(free[a], free[k]);
      M(a, a) += mu * c.D[free[a]] * c.D[free[a]];
      b[a] = -c.lm.g[free[a]];
    }
    for (const int k : free) d[k] = 0;  // re-solved below, against the variables already on their bounds
    const Eigen::VectorXd A_d = c.lm.A * d;
    for (Eigen::Index a = 0; a < F; ++a) b[a] -= A_d[free[a]];
    const Eigen::VectorXd d_free = M.ldlt().solve(b);
    std::vector<int> still_free;
    for (Eigen::Index a = 0; a < F; ++a) {
      const int k = free[a];
      const double to = c.x[k] + d_free[a];
      d[k] = std::clamp(to, c.lo[k], c.hi[k]) - c.x[k];
      if (to >= c.lo[k] && to <= c.hi[k]) still_free.push_back(k);
    }
    if (still_free.size() == free.size()) break;
    free = std::move(still_free);
  }
  return d;
}

// The Levenberg-Marquardt step inside the trust region |D d| <= radius: Gauss-Newton's (a vanishing mu) when
// it fits, else the mu whose step's length is the radius within the band (bisection in log mu: |D d(mu)| falls
// with mu, and P is small).
Eigen::VectorXd trust_region_step(const StepContext& c, double radius) {
  double mu_lo = 1e-14, mu_hi = 1e40;
  Eigen::VectorXd d = lm_step(c, mu_lo);
  if (scaled_norm(d, c.D) <= (1 + kRadiusBand) * radius) return d;
  for (int i = 0; i < kMuSearchSteps; ++i) {
    const double mu = std::sqrt(mu_lo * mu_hi);
    d = lm_step(c, mu);
    const double n = scaled_norm(d, c.D);
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
    case LmTermination::kConvergence: return "CONVERGENCE";
    case LmTermination::kNoConvergence: return "NO_CONVERGENCE";
    case LmTermination::kAborted: return "USER_FAILURE";
  }
  return "?";
}

namespace {

// One trial: the step inside `radius` from the context's point, projected, its cost and its decrease.
struct Trial {
  std::vector<double> x;
  std::vector<double> r;
  Eigen::VectorXd step;
  double cost = 0, predicted = 0, scaled_length = 0;
};

enum class TrialRun { kEvaluated, kTooShort, kAborted };

// Evaluates the step unless its scaled length is at most min_length (a wider region that changes nothing).
TrialRun try_step(const StepContext& c, double radius, Trial* t, double min_length = -1) {
  const Eigen::Index P = c.lm.g.size();
  t->x = project(c.x, trust_region_step(c, radius), c.pr);
  t->step.resize(P);
  for (Eigen::Index k = 0; k < P; ++k) t->step[k] = t->x[k] - c.x[k];
  t->predicted = c.lm.predicted_decrease(t->step);
  t->scaled_length = scaled_norm(t->step, c.D);
  if (t->scaled_length <= min_length) return TrialRun::kTooShort;
  t->r.resize(static_cast<std::size_t>(c.pr.num_residuals));
  if (!c.pr.residuals(t->x, &t->r)) return TrialRun::kAborted;
  t->cost = half_squared_norm(t->r);
  return TrialRun::kEvaluated;
}

void trace(const BoundedLmResult& res, const Trial& t, double radius, const char* what) {
  static const bool on = std::getenv("SB_LM_TRACE") != nullptr;
  if (on) {
    std::fprintf(stderr, "LM %3d cost %.8g trial %.8g predicted %.4g |Ds| %.3g radius %.3g %s x", res.iterations,
                 res.cost, t.cost, t.predicted, t.scaled_length, radius, what);
    for (double v : t.x) std::fprintf(stderr, " %.4g", v);
    std::fprintf(stderr, "\n");
  }
}

// After a step the model predicted well to the region's edge: a trial costs one evaluation against a Jacobian's P,
// so wider regions are tried from the same model while they lower the cost (MINPACK would grow the region 2x per
// Jacobian). *t and *radius become the best trial's. False when aborted.
bool widen(const StepContext& c, double* radius, Trial* t, BoundedLmResult* res) {
  for (int e = 0; e < kMaxExpansions; ++e) {
    Trial wider;
    const TrialRun run = try_step(c, kExpansion * *radius, &wider, kMinWidening * t->scaled_length);
    if (run == TrialRun::kAborted) return false;
    if (run == TrialRun::kTooShort) break;
    ++res->iterations;
    const bool better = wider.cost < t->cost;
    trace(*res, wider, kExpansion * *radius, better ? "wider: taken" : "wider: kept the last");
    if (!better) break;
    *t = std::move(wider);
    *radius *= kExpansion;
  }
  return true;
}

}  // namespace

BoundedLmResult minimize_bounded_lm(const BoundedLmProblem& pr, const std::vector<double>& x0,
                                    const BoundedLmOptions& o) {
  check(pr, x0);
  const int P = static_cast<int>(x0.size());
  BoundedLmResult res;
  res.x = project(x0, Eigen::VectorXd::Zero(P), pr);
  std::vector<double> r(static_cast<std::size_t>(pr.num_residuals)), J;
  const auto finish = [&](LmTermination t) {
    res.termination = t;
    return res;
  };
  if (!pr.residuals(res.x, &r)) return finish(LmTermination::kAborted);
  res.cost = half_squared_norm(r);
  if (o.on_iteration && !o.on_iteration(0, res.cost)) return finish(LmTermination::kAborted);
  Eigen::VectorXd D = Eigen::VectorXd::Zero(P);  // the columns' norms at x (Ceres's; MINPACK's never-decreasing
                                                 // ones re-tried one Gauss-Newton step: docs/performance.md)
  double radius = 0;
  std::unique_ptr<LocalModel> lm;
  int failures_in_a_row = 0;
  while (res.accepted < o.max_iterations && failures_in_a_row < kMaxFailuresInARow) {
    if (!lm) {  // at the start and after an accepted step; a rejected one keeps x and its model
      if (!pr.jacobian(res.x, r, &J)) return finish(LmTermination::kAborted);
      lm = std::make_unique<LocalModel>(J, r, P);
      D = lm->A.diagonal().cwiseMax(kMinDiagonal).cwiseSqrt();
      if (radius == 0) {
        const double xn = scaled_norm(Eigen::Map<const Eigen::VectorXd>(res.x.data(), P), D);
        radius = xn > 0 ? kRadiusFactor * xn : kRadiusFactor;
      }
      if (projected_gradient_norm(res.x, pr, lm->g) <= o.gradient_tolerance) return finish(LmTermination::kConvergence);
    }
    const StepContext c(res.x, pr, *lm, D);
    Trial t;
    if (try_step(c, radius, &t) == TrialRun::kAborted) return finish(LmTermination::kAborted);
    ++res.iterations;
    const double x_norm = Eigen::Map<const Eigen::VectorXd>(res.x.data(), P).norm();
    if (t.step.norm() <= o.parameter_tolerance * (x_norm + o.parameter_tolerance))
      return finish(LmTermination::kConvergence);
    const double actual = res.cost - t.cost;
    const double rho = t.predicted > 0 ? actual / t.predicted : -1;
    const bool accepted = rho > kMinRatio;
    // Converged: an accepted step changed the cost by less than the tolerance (Ceres's rule), or the model
    // predicts no more than that inside the region.
    const bool converged = std::abs(actual) <= o.function_tolerance * res.cost &&
                           (accepted || (t.predicted >= 0 && t.predicted <= o.function_tolerance * res.cost));
    if (rho < 0.25) {
      radius = shrink_factor(lm->g.dot(t.step), actual) * std::min(radius, t.scaled_length);
    } else if (rho > 0.75) {
      radius = std::max(radius, 2 * t.scaled_length);
    }
    trace(res, t, radius, accepted ? "accepted" : "rejected");
    if (accepted && rho > 0.75 && t.scaled_length >= (1 - kRadiusBand) * radius / 2 && !widen(c, &radius, &t, &res))
      return finish(LmTermination::kAborted);
    if (accepted) {
      res.x = t.x;
      res.cost = t.cost;
      r.swap(t.r);
      lm.reset();
      ++res.accepted;
      failures_in_a_row = 0;
    } else {
      ++failures_in_a_row;
    }
    if (o.on_iteration && !o.on_iteration(res.iterations, res.cost)) return finish(LmTermination::kAborted);
    if (converged || radius < kMinRadius) return finish(LmTermination::kConvergence);
  }
  return finish(failures_in_a_row < kMaxFailuresInARow ? LmTermination::kNoConvergence : LmTermination::kConvergence);
}

}  // namespace sb
