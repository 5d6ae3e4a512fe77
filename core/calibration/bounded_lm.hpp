// Levenberg-Marquardt for a least-squares problem with box bounds whose Jacobian is dear: every residual
// evaluation is a run of a shear model over a split's sample paths, every Jacobian one run per column.
//
// Why not Ceres here: with bounds, Ceres's trust-region minimiser projects each step by an Armijo line search
// that asks the gradient (a whole finite-difference Jacobian) at every probe and tests the Armijo condition along
// the unprojected step (its own comment calls the projection "incorrect and not terribly effective", ceres-solver
// GitHub #187); on the TacTip that was two Jacobians per iteration. Here a trial step costs one evaluation and an
// accepted step one Jacobian. docs/performance.md, "Fits: a projected Levenberg-Marquardt".
//
// The step (Moré's trust-region Levenberg-Marquardt as MINPACK's lmder takes it, with an active set for the box):
// variables at a bound whose gradient points out of the box are held; the others take
//   (J^T J + mu D^2) delta = -J^T r,   D = the columns' norms at x (at least 1e-3),
// with mu = 0 (Gauss-Newton) when |D delta| fits the trust radius, else the mu whose step has the radius's
// length. A variable the solution takes past its bound (or past its step cap, `max_step`) is put there and the
// others solved again, so the step stays a descent of the model; it is judged by the ratio of the actual to the
// predicted decrease. A failed step shrinks the radius below the step's length (x 0.1-0.5, interpolated); a
// step the model predicted well to the region's edge is followed by up to three trials in 4x wider regions
// from the same Jacobian, the best kept: a trial costs one evaluation, a Jacobian P.
//
// With SB_LM_TRACE set in the environment every trial is printed to stderr (cost, predicted decrease, step length,
// region, verdict, the point): how a fit's steps went, e.g. why a stage stopped where it did.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace sb {

struct BoundedLmProblem {
  std::vector<double> lo, hi;  // the box, per variable (lo <= hi)
  // The most a variable may move in one step (empty: no cap). Where a column is weak the scaled trust region
  // lets a variable jump across its range in one step (HydroShear's kappa_s to its bound 1e9 and mu to 0 on a twin
  // slice, a valley it never left); a cap keeps a step inside what the Jacobian there describes.
  std::vector<double> max_step;
  int num_residuals = 0;
  // r(x) into *r (num_residuals); false aborts the minimisation (a cancel).
  std::function<bool(const std::vector<double>& x, std::vector<double>* r)> residuals;
  // J(x) row-major (num_residuals x variables) into *J, given r = r(x); false aborts. Usually called right after
  // residuals(x); after a wider trial that was not taken, the last evaluation was elsewhere.
  std::function<bool(const std::vector<double>& x, const std::vector<double>& r, std::vector<double>* J)> jacobian;
};

struct BoundedLmOptions {
  // Accepted steps, i.e. Jacobians (a failed trial costs one evaluation and does not count: with bounds, Ceres's
  // line search cut a too-long step back within one iteration).
  int max_iterations = 50;
  double function_tolerance = 1e-6;    // stop when a step changes the cost by less than this fraction
  double parameter_tolerance = 1e-10;  // ... or moves x by less than this relative to |x|
  double gradient_tolerance = 1e-14;   // ... or the projected gradient's max norm is below this
  double initial_radius = 1e4;         // Ceres's initial trust-region radius
  // After the start and after every iteration: (iteration, cost); false aborts.
  std::function<bool(int, double)> on_iteration;
};

enum class LmTermination { kConvergence, kNoConvergence, kAborted };
// Ceres's words ("CONVERGENCE", "NO_CONVERGENCE", "USER_FAILURE"), which fit reports have always carried.
std::string to_string(LmTermination t);

struct BoundedLmResult {
  std::vector<double> x;  // the best point accepted (inside the box)
  double cost = 0;        // 1/2 |r(x)|^2
  int iterations = 0;     // trial steps, accepted or not: one evaluation each
  int accepted = 0;       // steps taken: one Jacobian each (after the start's)
  LmTermination termination = LmTermination::kNoConvergence;
};

// Starts from x0 projected onto the box.
BoundedLmResult minimize_bounded_lm(const BoundedLmProblem& problem, const std::vector<double>& x0,
                                    const BoundedLmOptions& options);

}  // namespace sb
