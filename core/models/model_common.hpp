#pragma once
// Pieces shared by the shear-model batches (hydroshear, fots, tacsl): the analytic flat-pad SDF fast
// path, the marker-grid structure used by separable Gaussian sums, and the adapter that turns a batch
// of one into a ShearModel.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <algorithm>
#include <cmath>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/models/model.hpp"

namespace sb {

// phi_E of the flat tsd/1 pad (x in [-hx, hx], y in [-hy, hy], z in [-thickness, 0]) without a virtual
// call: the same box distance as make_pad_sdf.
struct FlatPad {
  double hx = 0, hy = 0, thickness = 0;
  // Inline: HydroShear calls it for every candidate point.
  double value(const Vec3& p) const {
    // Box centred at (0, 0, -thickness/2) with half sizes (hx, hy, thickness/2), as make_pad_sdf.
    const double hz = 0.5 * thickness;
    const double qx = std::abs(p.x()) - hx;
    const double qy = std::abs(p.y()) - hy;
    const double qz = std::abs(p.z() + hz) - hz;
    const double ox = std::max(qx, 0.0), oy = std::max(qy, 0.0), oz = std::max(qz, 0.0);
    const double outside2 = ox * ox + oy * oy + oz * oz;
    if (outside2 > 0) return std::sqrt(outside2);
    return std::max(qx, std::max(qy, qz));
  }
};
// The flat pad of a sensor whose gel is "flat"; false otherwise.
bool flat_pad_of(const Sensor& sensor, FlatPad* pad);

// Markers laid out as a Cartesian grid x_c (cols, fastest) by y_r (rows) at one height z0, as
// marker_grid_px builds them. Gaussians of such markers factor per axis:
//   exp(-l |m_rc - a|^2) = exp(-l (x_c - a_x)^2) exp(-l (y_r - a_y)^2) exp(-l (z0 - a_z)^2).
struct MarkerGridLayout {
  bool is_grid = false;
  int rows = 0, cols = 0;
  std::vector<double> xs, ys;
  double z0 = 0;
};
MarkerGridLayout detect_marker_grid(const std::vector<Vec3>& p_EM);

// exp(-lambda (x_c - a)^2) for every coordinate x_c of one uniform grid axis with 2 std::exp calls
// instead of one per coordinate: with d_c = x_c - a and pitch h,
//   e_{c+1} = e_c r_c,  r_c = exp(-lambda (d_{c+1}^2 - d_c^2)) = exp(-lambda (h^2 + 2 h d_c)),
//   r_{c+1} = r_c q,    q = exp(-2 lambda h^2)  (a constant of the axis).
// Each e_c carries about 2c roundings (relative error ~1e-15 for 9 markers). The recurrence is used only
// while every exponent stays far from underflow (lambda d_c^2 <= kMaxExponent at both ends, so every
// factor is > e^-600); otherwise, and on a non-uniform axis, it calls std::exp per coordinate.
class GaussianAxis {
 public:
  GaussianAxis() = default;
  GaussianAxis(std::vector<double> coords, double lambda);
  int size() const { return static_cast<int>(x_.size()); }
  // e[c] = exp(-lambda (x_c - a)^2), c = 0..size()-1.
  void eval(double a, double* e) const;
  // The factored form for callers that batch their exps: with d_0 = x_0 - a,
  //   e[c] = exp(-lambda d_0^2) * ratio[c],  ratio[0] = 1, ratio[c+1] = ratio[c] r_c,  r_c = r_0 q^c,
  // where r_0 = exp(ratio_exponent(a)). lead_exponent(a) = -lambda d_0^2; max_exponent(a) =
  // lambda max_c d_c^2 bounds every partial product. false when the axis is not uniform.
  bool uniform() const { return uniform_; }
  double front() const { return x_.front(); }
  double back() const { return x_.back(); }
  double pitch() const { return h_; }
  double lambda() const { return lambda_; }
  double q() const { return q_; }
  double lead_exponent(double a) const { return -lambda_ * (x_.front() - a) * (x_.front() - a); }
  double ratio_exponent(double a) const { return -lambda_ * (h_ * h_ + 2 * h_ * (x_.front() - a)); }
  double max_exponent(double a) const {
    return lambda_ * std::max((x_.front() - a) * (x_.front() - a), (x_.back() - a) * (x_.back() - a));
  }
  // ratio[c] from r_0 (see above).
  void ratios(double r0, double* ratio) const {
    double e = 1, r = r0;
    for (std::size_t c = 0; c < x_.size(); ++c) {
      ratio[c] = e;
      e *= r;
      r *= q_;
    }
  }

 private:
  static constexpr double kMaxExponent = 300;
  std::vector<double> x_;
  double lambda_ = 0, h_ = 0, q_ = 1;
  bool uniform_ = false;
};

// exp(x[i]) in place for x in [-700, 700] (outside: undefined; callers guarantee it), branch-free so the loop
// vectorises: x = k ln2 + r with |r| <= ln2/2, exp(r) by its Taylor series to degree 12 (truncation < 3e-16 relative),
// times 2^k built in the exponent bits. Relative error a few ulp (tested against std::exp); the shear models call it on
// a few exponents per point instead of std::exp per marker.
void exp_in_place(double* x, int n);

// S[a * stride + c] += sum_{i < m} W[i * nw + a] X[i * stride + c] for a < nw, c < stride: the sum of m
// outer products (a small matrix product W^T X). X rows are padded to `stride` (a multiple of 4, zeros
// past the real columns) so the inner loop is whole vectors.
// W and X must stay readable for 64 doubles past their ends (the vectorised loop may over-read).
void add_outer_products(const double* W, int nw, const double* X, int stride, int m, double* S);

// Throws std::invalid_argument naming the model when a pose is not finite. A string_view: called per
// slot and step, it must not build a std::string ("tacsl-normalized" is past the small-string buffer).
void require_finite_pose(const Pose& X_EI, std::string_view model_id);

// Runs body(range) over the slots [0, n) of a batched step: inline for a single slot (the workbench's one
// sensor pays no task overhead), else as TBB tasks of `grain` slots.
template <class Body>
void for_each_slot_range(int n, int grain, const Body& body) {
  if (n == 1)
    body(tbb::blocked_range<int>(0, 1));
  else
    tbb::parallel_for(tbb::blocked_range<int>(0, n, grain), body);
}

// Diagnostics of a model that tracks no surface points (FOTS, TacSL): the field, and a marker counts as
// in contact where it is inside the indenter (phi_I < 0).
void marker_contact_diagnostics(const Vec2* disp, const std::vector<double>& phi_I, FieldOutput& out);

}  // namespace sb
