#include "core/models/model_common.hpp"
#include "core/base/vector_clones.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace sb {

bool flat_pad_of(const Sensor& sensor, FlatPad* pad) {
  if (sensor.gel.surface != "flat") return false;
  pad->hx = 0.5 * sensor.gel.size_m.x();
  pad->hy = 0.5 * sensor.gel.size_m.y();
  pad->thickness = sensor.gel.thickness_m;
  return true;
}

MarkerGridLayout detect_marker_grid(const std::vector<Vec3>& p_EM) {
  // Relative tolerance on coordinates when deciding that markers share a row, column or height.
  constexpr double kGridTolerance = 1e-9;
  MarkerGridLayout g;
  const std::size_t n = p_EM.size();
  if (n == 0) return g;
  std::size_t cols = 1;
  while (cols < n && std::abs(p_EM[cols].y() - p_EM[0].y()) < kGridTolerance) ++cols;
  if (n % cols != 0) return g;
  const std::size_t rows = n / cols;
  g.xs.resize(cols);
  g.ys.resize(rows);
  for (std::size_t c = 0; c < cols; ++c) g.xs[c] = p_EM[c].x();
  for (std::size_t r = 0; r < rows; ++r) g.ys[r] = p_EM[r * cols].y();
  g.z0 = p_EM[0].z();
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t c = 0; c < cols; ++c) {
      const Vec3& m = p_EM[r * cols + c];
      if (std::abs(m.x() - g.xs[c]) > kGridTolerance || std::abs(m.y() - g.ys[r]) > kGridTolerance ||
          std::abs(m.z() - g.z0) > kGridTolerance)
        return MarkerGridLayout{};
    }
  g.rows = static_cast<int>(rows);
  g.cols = static_cast<int>(cols);
  g.is_grid = true;
  return g;
}

GaussianAxis::GaussianAxis(std::vector<double> coords, double lambda) : x_(std::move(coords)), lambda_(lambda) {
  // A pitch is uniform when every step equals the first to 1e-12 relative: the exponent error of
  // treating it as exact is then 2 lambda |d| |dh| ~ 1e-16 for the workload's sizes.
  constexpr double kPitchTolerance = 1e-12;
  const std::size_t n = x_.size();
  uniform_ = n >= 2;
  if (uniform_) {
    h_ = x_[1] - x_[0];
    for (std::size_t c = 1; c + 1 < n && uniform_; ++c)
      uniform_ = std::abs((x_[c + 1] - x_[c]) - h_) <= kPitchTolerance * std::abs(h_);
  }
  q_ = std::exp(-2 * lambda_ * h_ * h_);
}

void GaussianAxis::eval(double a, double* e) const {
  const int n = size();
  const double d0 = x_.empty() ? 0 : x_.front() - a;
  const double dn = x_.empty() ? 0 : x_.back() - a;
  if (!uniform_ || lambda_ * std::max(d0 * d0, dn * dn) > kMaxExponent) {
    for (int c = 0; c < n; ++c) e[c] = std::exp(-lambda_ * (x_[c] - a) * (x_[c] - a));
    return;
  }
  double ec = std::exp(-lambda_ * d0 * d0);
  double r = std::exp(-lambda_ * (h_ * h_ + 2 * h_ * d0));
  for (int c = 0; c < n; ++c) {
    e[c] = ec;
    ec *= r;
    r *= q_;
  }
}

// Both loops are compiled twice, for AVX2/FMA and the baseline (core/base/vector_clones.hpp).

namespace {

// Register-blocked form for a compile-time row length: two rows of S stay in registers (6 AVX vectors
// for ST = 12) while the points stream past, so S is loaded and stored once per pair of rows.
// Always inlined, so each target clone of the caller compiles it for its own vector unit.
template <int ST>
[[gnu::always_inline]] inline void add_outer_products_fixed(const double* W, int nw, const double* X, int m,
                                                            double* S) {
  int a = 0;
  for (; a + 2 <= nw; a += 2) {
    double acc0[ST] = {}, acc1[ST] = {};
    for (int i = 0; i < m; ++i) {
      const double* x = X + static_cast<std::ptrdiff_t>(i) * ST;
      const double w0 = W[static_cast<std::ptrdiff_t>(i) * nw + a], w1 = W[static_cast<std::ptrdiff_t>(i) * nw + a + 1];
      for (int c = 0; c < ST; ++c) {
        acc0[c] += w0 * x[c];
        acc1[c] += w1 * x[c];
      }
    }
    for (int c = 0; c < ST; ++c) {
      S[a * ST + c] += acc0[c];
      S[(a + 1) * ST + c] += acc1[c];
    }
  }
  for (; a < nw; ++a)
    for (int i = 0; i < m; ++i)
      for (int c = 0; c < ST; ++c) S[a * ST + c] += W[static_cast<std::ptrdiff_t>(i) * nw + a] * X[i * ST + c];
}

}  // namespace

SB_VECTOR_CLONES
void add_outer_products(const double* W, int nw, const double* X, int stride, int m, double* S) {
  if (stride == 12) return add_outer_products_fixed<12>(W, nw, X, m, S);  // 9-column grids (GelSight Mini)
  if (stride == 8) return add_outer_products_fixed<8>(W, nw, X, m, S);
  for (int i = 0; i < m; ++i) {
    const double* x = X + static_cast<std::ptrdiff_t>(i) * stride;
    const double* w = W + static_cast<std::ptrdiff_t>(i) * nw;
    for (int a = 0; a < nw; ++a) {
      const double wa = w[a];
      double* s = S + static_cast<std::ptrdiff_t>(a) * stride;
      SB_IVDEP
      for (int c = 0; c < stride; ++c) s[c] += wa * x[c];
    }
  }
}

SB_VECTOR_CLONES
void exp_in_place(double* x, int n) {
  constexpr double kLog2e = 1.4426950408889634;
  // ln 2 in two parts: the first has few enough bits that k * kLn2Hi is exact for |k| < 2^11.
  constexpr double kLn2Hi = 0.693145751953125;
  constexpr double kLn2Lo = 1.42860682030941723212e-6;
  constexpr double kShifter = 0x1.8p52;  // adding it rounds to an integer held in the low mantissa bits
  SB_IVDEP
  for (int i = 0; i < n; ++i) {
    const double v = x[i];  // the caller keeps it in [-700, 700]
    const double t = v * kLog2e + kShifter;
    const double k = t - kShifter;
    const double r = (v - k * kLn2Hi) - k * kLn2Lo;
    // Taylor coefficients 1/j!, Horner from degree 12.
    double p = 1.0 / 479001600;
    p = p * r + 1.0 / 39916800;
    p = p * r + 1.0 / 3628800;
    p = p * r + 1.0 / 362880;
    p = p * r + 1.0 / 40320;
    p = p * r + 1.0 / 5040;
    p = p * r + 1.0 / 720;
    p = p * r + 1.0 / 120;
    p = p * r + 1.0 / 24;
    p = p * r + 1.0 / 6;
    p = p * r + 0.5;
    p = p * r + 1.0;
    p = p * r + 1.0;
    // 2^k: k + 1023 in the exponent field (the low bits of t hold k in two's complement).
    const std::uint64_t bits = (std::bit_cast<std::uint64_t>(t) + 1023) << 52;
    x[i] = p * std::bit_cast<double>(bits);
  }
}

void require_finite_pose(const Pose& X_EI, std::string_view model_id) {
  if (!is_finite(X_EI)) throw std::invalid_argument(std::string(model_id) + ": the indenter pose X_EI is not finite");
}

void marker_contact_diagnostics(const Vec2* disp, const std::vector<double>& phi_I, FieldOutput& out) {
  const std::size_t nm = phi_I.size();
  out.disp_px.assign(disp, disp + nm);
  out.marker_in_contact.resize(nm);
  for (std::size_t j = 0; j < nm; ++j) out.marker_in_contact[j] = phi_I[j] < 0 ? 1 : 0;
  out.p_EP.clear();
  out.anchor_EP.clear();
  out.point_state.clear();
}

}  // namespace sb
