// The rest grid's lattice and lens (rest_grid_lens.hpp).
#include "core/loop/rest_grid_lens.hpp"
#include "core/base/format.hpp"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <queue>

namespace sb {
namespace {

double half_diagonal_sq(const Camera& camera) {
  return 0.25 * (double(camera.width_px) * camera.width_px + double(camera.height_px) * camera.height_px);
}

// Markers nearest the principal point whose neighbour offsets give the lattice's two steps.
constexpr int kSeedNeighbourhood = 9;
// Two offsets are not collinear when the angle between them is at least 30 degrees (|sin| >= 0.5); a square
// lattice's second step is at 90, a hexagonal one's at 60.
constexpr double kMinStepSine = 0.5;

double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// The two shortest non-collinear offsets from the markers nearest the principal point to any other marker:
// a the shortest, b the shortest at >= 30 degrees from it, signed so that a.x >= 0 (a.y > 0 when vertical)
// and a x b > 0.
bool lattice_steps(const std::vector<Vec2>& p, const std::vector<int>& finite, const std::vector<int>& central, Vec2* a,
                   Vec2* b) {
  std::vector<Vec2> offsets;
  for (int i : central)
    for (int j : finite)
      if (j != i && (p[j] - p[i]).norm() > 0) offsets.push_back(p[j] - p[i]);
  if (offsets.empty()) return false;
  const auto shorter = [](const Vec2& u, const Vec2& v) {
    const double nu = u.squaredNorm(), nv = v.squaredNorm();
    return nu != nv ? nu < nv : (u.x() != v.x() ? u.x() < v.x() : u.y() < v.y());  // deterministic ties
  };
  *a = *std::min_element(offsets.begin(), offsets.end(), shorter);
  if (a->x() < 0 || (a->x() == 0 && a->y() < 0)) *a = -*a;
  bool found = false;
  for (const Vec2& o : offsets) {
    if (std::abs(cross(*a, o)) < kMinStepSine * a->norm() * o.norm()) continue;
    if (!found || shorter(o, *b)) *b = o, found = true;
  }
  if (found && cross(*a, *b) < 0) *b = -*b;
  return found;
}

// rest = D(o + A n), templated for Ceres. x = {o (2), A (4, row-major), k1}.
struct LatticeResidual {
  LatticeResidual(const Vec2& rest, const Eigen::Vector2i& n, const Vec2& c, double hd2)
      : rest_(rest), n_(n), c_(c), hd2_(hd2) {}
  template <typename T>
  bool operator()(const T* o, const T* A, const T* k1, T* r) const {
    const T ux = o[0] + A[0] * double(n_.x()) + A[1] * double(n_.y()) - c_.x();
    const T uy = o[1] + A[2] * double(n_.x()) + A[3] * double(n_.y()) - c_.y();
    const T g = 1.0 + k1[0] * (ux * ux + uy * uy) / hd2_;
    r[0] = c_.x() + ux * g - rest_.x();
    r[1] = c_.y() + uy * g - rest_.y();
    return true;
  }
  Vec2 rest_;
  Eigen::Vector2i n_;
  Vec2 c_;
  double hd2_;
};

std::string fmt(const char* f, double v) { return format_number(v, f, "nan"); }

}  // namespace

Vec2 lens_distort_px(const Camera& camera, double k1, const Vec2& p_px) {
  const Vec2 q = p_px - camera.principal_px;
  return camera.principal_px + q * (1.0 + k1 * q.squaredNorm() / half_diagonal_sq(camera));
}

LatticeIndices assign_lattice_indices(const std::vector<Vec2>& rest_px, const Vec2& principal_px) {
  LatticeIndices out;
  const int N = int(rest_px.size());
  out.index.assign(N, Eigen::Vector2i::Zero());
  out.assigned.assign(N, 0);
  std::vector<int> finite;
  for (int i = 0; i < N; ++i)
    if (rest_px[i].allFinite()) finite.push_back(i);
  if (finite.size() < 4) return out;
  // The markers nearest the principal point (ties by storage index, for determinism only).
  std::vector<int> by_centre = finite;
  std::stable_sort(by_centre.begin(), by_centre.end(), [&](int i, int j) {
    return (rest_px[i] - principal_px).squaredNorm() < (rest_px[j] - principal_px).squaredNorm();
  });
  const std::vector<int> central(by_centre.begin(),
                                 by_centre.begin() + std::min<std::size_t>(kSeedNeighbourhood, by_centre.size()));
  if (!lattice_steps(rest_px, finite, central, &out.step_a_px, &out.step_b_px)) return out;
  const Vec2 steps[2] = {out.step_a_px, out.step_b_px};

  std::map<std::pair<int, int>, int> at;  // index -> marker
  const auto key = [](const Eigen::Vector2i& n) { return std::make_pair(n.x(), n.y()); };
  // Grown outwards: the marker nearest the principal point first (its distance orders the queue).
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  const int seed = central.front();
  out.assigned[seed] = 1;
  at[{0, 0}] = seed;
  queue.push({0.0, seed});
  while (!queue.empty()) {
    const int i = queue.top().second;
    queue.pop();
    for (int axis = 0; axis < 2; ++axis)
      for (int sign : {1, -1}) {
        const Eigen::Vector2i e = sign * Eigen::Vector2i::Unit(axis);
        const Eigen::Vector2i n = out.index[i] + e;
        if (at.count(key(n))) continue;
        // The step: the spacing this marker already has on the other side, else the seed's.
        const auto behind = at.find(key(out.index[i] - e));
        const Vec2 step = behind != at.end() ? Vec2(rest_px[i] - rest_px[behind->second]) : Vec2(sign * steps[axis]);
        const Vec2 predicted = rest_px[i] + step;
        int nearest = -1;
        double best = std::numeric_limits<double>::infinity();
        for (int j : finite) {
          const double d = (rest_px[j] - predicted).squaredNorm();
          if (d < best) best = d, nearest = j;
        }
        if (nearest < 0 || out.assigned[nearest] || std::sqrt(best) > kLatticeAssignFraction * step.norm()) continue;
        out.assigned[nearest] = 1;
        out.index[nearest] = n;
        at[key(n)] = nearest;
        queue.push({(rest_px[nearest] - principal_px).norm(), nearest});
      }
  }
  out.count = int(at.size());
  return out;
}

namespace {

// k1's standard error: the Jacobian at the optimum, (J^T J)^-1 times the residual variance SSE / (2N - 7)
// (o: 2, A: 4, k1: 1 parameters; k1 is column 6). NaN without degrees of freedom or for a singular J^T J.
double k1_standard_error(ceres::Problem& problem, double sse, int markers) {
  ceres::CRSMatrix crs;
  problem.Evaluate(ceres::Problem::EvaluateOptions(), nullptr, nullptr, nullptr, &crs);
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int r = 0; r < crs.num_rows; ++r)
    for (int e = crs.rows[r]; e < crs.rows[r + 1]; ++e) J(r, crs.cols[e]) = crs.values[e];
  const int dof = 2 * markers - 7;
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(J.transpose() * J);
  if (dof <= 0 || !lu.isInvertible()) return std::numeric_limits<double>::quiet_NaN();
  return std::sqrt(lu.inverse()(6, 6) * sse / dof);
}

// Why the fitted grid is not a lattice the lens can be read from ("" when it is).
std::string lattice_verdict(const RestGridLens& fit, const ceres::Solver::Summary& summary) {
  if (summary.termination_type == ceres::FAILURE || !std::isfinite(fit.k1))
    return "the lattice fit did not converge (" + summary.message + ")";
  if (fit.span.minCoeff() < kMinLatticeSpan)
    return "the markers span " + std::to_string(fit.span.x()) + " x " + std::to_string(fit.span.y()) +
           " lattice indices (< " + std::to_string(kMinLatticeSpan) + " along an axis)";
  if (!(fit.rms_px < kMaxLatticeRmsPitchFraction * fit.pitch_px))
    return "RMS " + fmt("%.2f", fit.rms_px) + " px about the lattice (>= " + fmt("%.2g", kMaxLatticeRmsPitchFraction) +
           " of the " + fmt("%.1f", fit.pitch_px) + " px pitch)";
  return "";
}

}  // namespace

RestGridLens rest_grid_lens(const Camera& camera, const std::vector<Vec2>& rest_px) {
  RestGridLens fit;
  fit.indices = assign_lattice_indices(rest_px, camera.principal_px);
  const LatticeIndices& L = fit.indices;
  std::vector<int> used;
  for (int i = 0; i < int(rest_px.size()); ++i)
    if (L.assigned[i]) used.push_back(i);
  fit.markers_used = int(used.size());
  if (fit.markers_used < kMinLatticeMarkers) {
    fit.why_not = std::to_string(fit.markers_used) + " markers on a lattice (< " + std::to_string(kMinLatticeMarkers) +
                  ")";
    return fit;
  }
  Eigen::Vector2i lo = L.index[used[0]], hi = lo;
  for (int i : used) lo = lo.cwiseMin(L.index[i]), hi = hi.cwiseMax(L.index[i]);
  fit.span = hi - lo + Eigen::Vector2i::Ones();

  // Start: the affine lattice by linear least squares (k1 = 0): rest = o + A n.
  Eigen::MatrixXd X(used.size(), 3);
  Eigen::MatrixXd Y(used.size(), 2);
  for (std::size_t r = 0; r < used.size(); ++r) {
    const int i = used[r];
    X.row(r) << 1.0, double(L.index[i].x()), double(L.index[i].y());
    Y.row(r) = rest_px[i].transpose();
  }
  const Eigen::MatrixXd B = X.colPivHouseholderQr().solve(Y);  // rows: o, A e_x, A e_y
  double o[2] = {B(0, 0), B(0, 1)};
  double A[4] = {B(1, 0), B(2, 0), B(1, 1), B(2, 1)};
  double k1 = 0.0;

  const double hd2 = half_diagonal_sq(camera);
  ceres::Problem problem;
  for (int i : used)
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<LatticeResidual, 2, 2, 4, 1>(
                                 new LatticeResidual(rest_px[i], L.index[i], camera.principal_px, hd2)),
                             nullptr, o, A, &k1);
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = 100;
  so.function_tolerance = 1e-15;
  so.parameter_tolerance = 1e-15;
  so.gradient_tolerance = 1e-18;
  so.num_threads = 1;
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);

  fit.origin_px = Vec2(o[0], o[1]);
  fit.A << A[0], A[1], A[2], A[3];
  fit.k1 = k1;
  const double pa = fit.A.col(0).norm(), pb = fit.A.col(1).norm();
  fit.pitch_px = std::min(pa, pb);
  fit.pitch_long_px = std::max(pa, pb);
  double sse = 0, shift = 0;
  for (int i : used) {
    const Vec2 u = fit.origin_px + fit.A * L.index[i].cast<double>();
    sse += (lens_distort_px(camera, k1, u) - rest_px[i]).squaredNorm();
    shift += (lens_distort_px(camera, k1, u) - u).squaredNorm();
  }
  const int N = fit.markers_used;
  fit.rms_px = std::sqrt(sse / N);
  fit.shift_rms_px = std::sqrt(shift / N);

  fit.k1_stderr = k1_standard_error(problem, sse, N);
  fit.why_not = lattice_verdict(fit, summary);
  fit.is_lattice = fit.why_not.empty();
  return fit;
}

Vec2 rest_grid_node_px(const Camera& camera, const RestGridLens& fit, const Eigen::Vector2i& n) {
  return lens_distort_px(camera, fit.k1, fit.origin_px + fit.A * n.cast<double>());
}

std::string describe(const RestGridLens& fit) {
  if (!fit.is_lattice) return "not a lattice (" + fit.why_not + ")";
  return "a lattice of " + std::to_string(fit.markers_used) + " markers (" + std::to_string(fit.span.x()) + " x " +
         std::to_string(fit.span.y()) + " indices, pitch " + fmt("%.1f", fit.pitch_px) +
         (fit.pitch_long_px > 1.01 * fit.pitch_px ? fmt(" x %.1f", fit.pitch_long_px) : std::string()) +
         " px) with k1 " + fmt("%.4f", fit.k1) + " +- " + fmt("%.2g", fit.k1_stderr) + ", RMS " +
         fmt("%.3g", fit.rms_px) + " px";
}

}  // namespace sb
