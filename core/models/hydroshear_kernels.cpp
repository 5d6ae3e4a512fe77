#include "core/models/hydroshear_kernels.hpp"

#include <cmath>
#include <cstring>

#include "core/base/vector_clones.hpp"

namespace sb::hydroshear_kernels {

// Selects instead of std::max / branches: the loops stay branch-free, so they vectorise.
namespace {
// GCC notes that a 32-byte vector passed by value has another ABI with AVX; these helpers are always
// inlined, never called across that boundary.
#pragma GCC diagnostic ignored "-Wpsabi"
using v4d = double __attribute__((vector_size(32)));
[[gnu::always_inline]] inline v4d load4(const double* p) {
  v4d v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
using v8f = float __attribute__((vector_size(32)));
using v4f = float __attribute__((vector_size(16)));
[[gnu::always_inline]] inline v4f load4f(const float* p) {
  v4f v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
[[gnu::always_inline]] inline void store4f(float* p, v4f v) { std::memcpy(p, &v, sizeof v); }
[[gnu::always_inline]] inline v4f to_float(v4d v) { return __builtin_convertvector(v, v4f); }

inline double relu(double v) { return v > 0 ? v : 0.0; }
inline double max2(double a, double b) { return a > b ? a : b; }
}  // namespace

SB_VECTOR_CLONES
void transform_points(const double* r, const double* t, const double* x, const double* y, const double* z, int n,
                      double* ox, double* oy, double* oz) {
  const double r0 = r[0], r1 = r[1], r2 = r[2], r3 = r[3], r4 = r[4], r5 = r[5], r6 = r[6], r7 = r[7], r8 = r[8];
  const double t0 = t[0], t1 = t[1], t2 = t[2];
  SB_IVDEP
  for (int i = 0; i < n; ++i) {
    const double a = x[i], b = y[i], c = z[i];
    ox[i] = r0 * a + r1 * b + r2 * c + t0;
    oy[i] = r3 * a + r4 * b + r5 * c + t1;
    oz[i] = r6 * a + r7 * b + r8 * c + t2;
  }
}

SB_VECTOR_CLONES
void flat_pad_phi(const FlatPad& pad, const double* shift, const double* x, const double* y, const double* z, int n,
                  double* phi) {
  const double hx = pad.hx, hy = pad.hy, hz = 0.5 * pad.thickness;
  const double sx = shift[0], sy = shift[1], sz = shift[2];
  SB_IVDEP
  for (int i = 0; i < n; ++i) {
    const double qx = std::fabs(x[i] + sx) - hx;
    const double qy = std::fabs(y[i] + sy) - hy;
    const double qz = std::fabs(z[i] + sz + hz) - hz;
    const double ox = relu(qx), oy = relu(qy), oz = relu(qz);
    const double outside2 = ox * ox + oy * oy + oz * oz;
    const double inside = max2(qx, max2(qy, qz));
    phi[i] = outside2 > 0 ? std::sqrt(outside2) : inside;
  }
}

namespace {
// The loop of advance_points; kNormalZ: n = +z for every point (the authors' split), its columns unread.
template <bool kNormalZ>
[[gnu::always_inline]] inline void advance_loop(const AdvanceColumns& c, double cone, int n, double* ux, double* uy,
                                                double* uz, double* un, std::uint8_t* slip) {
  SB_IVDEP
  for (int i = 0; i < n; ++i) {
    // In-gel fraction of the segment; 0/0 (s unchanged) is 1 as in the authors' code (s < 0 here).
    const double s = c.s[i], sp = c.s_prev[i];
    const double den = sp - s;
    const double den_safe = den != 0 ? den : 1.0;
    const double alpha = den != 0 ? (relu(-s) - relu(-sp)) / den_safe : 1.0;
    // Trial state: old state minus the point's in-gel motion, split along n.
    const double tx = c.ox[i] + alpha * (c.qx[i] - c.px[i]);
    const double ty = c.oy[i] + alpha * (c.qy[i] - c.py[i]);
    const double tz = c.oz[i] + alpha * (c.qz[i] - c.pz[i]);
    const double nx = kNormalZ ? 0.0 : c.nx[i], ny = kNormalZ ? 0.0 : c.ny[i], nz = kNormalZ ? 1.0 : c.nz[i];
    const double tn = tx * nx + ty * ny + tz * nz;
    const double utx = tx - tn * nx, uty = ty - tn * ny, utz = tz - tn * nz;
    const double u_n = relu(tn);
    // The cone |K u_t| <= mu E u_n, by exact projection (the authors divide by |f_t| + 1e-8).
    const double cap = cone * u_n;
    const double ut_norm = std::sqrt(utx * utx + uty * uty + utz * utz);
    const bool slipping = ut_norm > cap;
    const double scale = slipping ? cap / (ut_norm > 0 ? ut_norm : 1.0) : 1.0;
    ux[i] = u_n * nx + utx * scale;
    uy[i] = u_n * ny + uty * scale;
    uz[i] = u_n * nz + utz * scale;
    un[i] = u_n;
    slip[i] = slipping ? 1 : 0;
  }
}
}  // namespace

SB_VECTOR_CLONES
void advance_points(const AdvanceColumns& in, bool normal_z, double cone, int n, double* ux, double* uy, double* uz,
                    double* un, std::uint8_t* slip) {
  const AdvanceColumns c = in;  // a local copy: the outputs cannot alias it
  if (normal_z)
    advance_loop<true>(c, cone, n, ux, uy, uz, un, slip);
  else
    advance_loop<false>(c, cone, n, ux, uy, uz, un, slip);
}

namespace {
// One point's weight w and term v = -w f^xy (the paper's or the code's weight; split along n or +z).
template <bool kWeightPaper, bool kNormalZ>
[[gnu::always_inline]] inline void point_term(const ShearColumns& c, const PointConstants& k, int i, double& vx,
                                              double& vy, double& w) {
  const double u_n = c.un[i];
  const double nx = kNormalZ ? 0.0 : c.nx[i], ny = kNormalZ ? 0.0 : c.ny[i];
  const double fx = k.E * u_n * nx + k.K * (c.ux[i] - u_n * nx);
  const double fy = k.E * u_n * ny + k.K * (c.uy[i] - u_n * ny);
  w = kWeightPaper ? -c.phi[i] : k.E * u_n;
  vx = -w * fx;
  vy = -w * fy;
}

// The loop of point_operands for one weight choice and split normal: a select on a loop-invariant bool stops
// GCC's vectoriser, four instantiations do not.
template <bool kWeightPaper, bool kNormalZ>
[[gnu::always_inline]] inline void point_operands_loop(const ShearColumns& c, const PointConstants& k, int n,
                                                       double* vx, double* vy, double* w, double* ax, double* ay,
                                                       double* az) {
  SB_IVDEP
  for (int i = 0; i < n; ++i) {
    point_term<kWeightPaper, kNormalZ>(c, k, i, vx[i], vy[i], w[i]);
    ax[i] = c.px[i] + c.ux[i] + k.shift_x;
    ay[i] = c.py[i] + c.uy[i] + k.shift_y;
    az[i] = c.pz[i] + c.uz[i];
  }
}
}  // namespace

SB_VECTOR_CLONES
void point_operands(const ShearColumns& in, const PointConstants& constants, int n, const PointOperands& out) {
  // Local copies: the compiler cannot prove that the outputs do not alias a referenced struct.
  const ShearColumns c = in;
  const PointConstants k = constants;
  double *vx = out.vx, *vy = out.vy, *w = out.w, *ax = out.ax, *ay = out.ay, *az = out.az;
  if (k.weight_paper)
    k.normal_z ? point_operands_loop<true, true>(c, k, n, vx, vy, w, ax, ay, az)
               : point_operands_loop<true, false>(c, k, n, vx, vy, w, ax, ay, az);
  else
    k.normal_z ? point_operands_loop<false, true>(c, k, n, vx, vy, w, ax, ay, az)
               : point_operands_loop<false, false>(c, k, n, vx, vy, w, ax, ay, az);
}

SB_VECTOR_CLONES
int axis_exponents(const double* ax, const double* ay, const double* az, const AxisConstants& constants, int n,
                   const AxisExponents& out, std::uint8_t* fast) {
  const AxisConstants k = constants;
  const double l = k.lambda;
  double *ex0 = out.x0, *rx = out.rx, *ey0 = out.y0, *ry = out.ry;
  int slow = 0;
  SB_IVDEP
  for (int i = 0; i < n; ++i) {
    const double dx0 = k.x0 - ax[i], dxn = k.xn - ax[i], dy0 = k.y0 - ay[i], dyn = k.yn - ay[i], dz = k.z0 - az[i];
    const double lz = l * dz * dz;
    const bool ok = l * max2(dx0 * dx0, dxn * dxn) + lz <= k.max_total_exponent &&
                    l * max2(dy0 * dy0, dyn * dyn) <= k.max_total_exponent;
    ex0[i] = ok ? -l * dx0 * dx0 - lz : 0.0;
    ey0[i] = ok ? -l * dy0 * dy0 : 0.0;
    rx[i] = ok ? -l * (k.hx * k.hx + 2 * k.hx * dx0) : 0.0;
    ry[i] = ok ? -l * (k.hy * k.hy + 2 * k.hy * dy0) : 0.0;
    fast[i] = ok ? 1 : 0;
    slow += ok ? 0 : 1;
  }
  return slow;
}

namespace {
// The kernels below write their loops out: a lambda's body can be compiled out of line for the baseline
// target (see for_row_blocks), and these loops are the hot ones.
// The running row of the y factor at row 0: fast_i gy0_i.
[[gnu::always_inline]] inline void y_factor_start(const double* e_y0, const std::uint8_t* fast, int m, double* run) {
  SB_IVDEP
  for (int i = 0; i < m; ++i) {
    const double g = e_y0[i];  // loaded unconditionally: a conditional load stops vectorisation
    run[i] = fast[i] ? g : 0.0;
  }
}

// Four values of T: the recurrence's doubles rounded (float) or kept (double), and their loads and stores.
template <typename T>
struct Four;
template <>
struct Four<float> {
  using type = v4f;
  static type from(v4d v) { return to_float(v); }
  static type load(const float* p) { return load4f(p); }
  static void store(float* p, type v) { store4f(p, v); }
};
template <>
struct Four<double> {
  using type = v4d;
  static type from(v4d v) { return v; }
  static type load(const double* p) { return load4(p); }
  static void store(double* p, type v) { std::memcpy(p, &v, sizeof v); }
};

template <typename T>
[[gnu::always_inline]] inline T* row_of(T* base, int r, int m) {
  return base + static_cast<std::ptrdiff_t>(r) * m;
}

// Rows cols..round_up(cols, 3)-1 of an x-factor block: the products read them.
template <typename T>
[[gnu::always_inline]] inline void zero_padding_rows(T* block, int cols, int m) {
  const int cols_pad = (cols + 2) / 3 * 3;
  for (int c = cols; c < cols_pad; ++c) std::memset(row_of(block, c, m), 0, sizeof(T) * m);
}

// The operand builders run four points at a time with each axis' recurrence held in registers (in
// double: its start may be far below float's range while a later marker's factor is not), storing each
// marker's factor as T. Loops over the points with the rows outside kept the recurrence in memory.
template <typename T>
[[gnu::always_inline]] inline void term_operands_impl(const AxisFactors& e, const TermWeights<T>& v, const GridAxes& g,
                                                      int m, T* X, T* W, double* run) {
  using F = Four<T>;
  const double *e_x0 = e.x0, *e_rx = e.rx, *e_y0 = e.y0, *e_ry = e.ry;
  const T *vx = v.vx, *vy = v.vy, *w = v.w;
  const int rows = g.rows, cols = g.cols;
  const double qx = g.qx, qy = g.qy;
  for (int i = 0; i < m; i += 4) {
    v4d g = load4(e_x0 + i), ratio = load4(e_rx + i);
    for (int c = 0; c < cols; ++c) {
      if (c > 0) g *= ratio, ratio *= qx;
      F::store(row_of(X, c, m) + i, F::from(g));
    }
  }
  zero_padding_rows(X, cols, m);
  y_factor_start(e_y0, v.fast, m, run);
  for (int i = 0; i < m; i += 4) {
    v4d g = load4(run + i), ratio = load4(e_ry + i);
    const typename F::type vx4 = F::load(vx + i), vy4 = F::load(vy + i);
    const typename F::type w4 = w != nullptr ? F::load(w + i) : typename F::type{};
    for (int r = 0; r < rows; ++r) {
      if (r > 0) g *= ratio, ratio *= qy;
      const typename F::type gt = F::from(g);
      F::store(row_of(W, r, m) + i, vx4 * gt);
      F::store(row_of(W, rows + r, m) + i, vy4 * gt);
      if (w != nullptr) F::store(row_of(W, 2 * rows + r, m) + i, w4 * gt);
    }
  }
}

template <typename T>
[[gnu::always_inline]] inline void aniso_operands_impl(const AxisFactors& e, const TermWeights<T>& v, const double* ax,
                                                       const double* ay, double kl, const GridAxes& g, int m, T* X3,
                                                       T* W4, double* run) {
  using F = Four<T>;
  const double *e_x0 = e.x0, *e_rx = e.rx, *e_y0 = e.y0, *e_ry = e.ry;
  const T *vx = v.vx, *vy = v.vy;
  const double *xs = g.xs, *ys = g.ys;
  const int rows = g.rows, cols = g.cols;
  const double qx = g.qx, qy = g.qy;
  using V = typename F::type;
  const int cols_pad = (cols + 2) / 3 * 3;
  T* XC = X3;
  T* XA = row_of(X3, cols_pad, m);
  T* XB = row_of(X3, 2 * cols_pad, m);
  const T klt = static_cast<T>(kl);
  for (int i = 0; i < m; i += 4) {
    v4d g = load4(e_x0 + i), ratio = load4(e_rx + i);
    const v4d a = load4(ax + i);
    for (int c = 0; c < cols; ++c) {
      if (c > 0) g *= ratio, ratio *= qx;
      const V e = F::from(g), dx = F::from(xs[c] - a);  // the offset in double, then rounded
      F::store(row_of(XC, c, m) + i, e);
      F::store(row_of(XA, c, m) + i, e * (1 + klt * dx * dx));
      F::store(row_of(XB, c, m) + i, e * dx);
    }
  }
  for (T* block : {XC, XA, XB}) zero_padding_rows(block, cols, m);
  T* W1 = W4;
  T* WB = row_of(W4, rows, m);
  T* WC = row_of(W4, 3 * rows, m);
  y_factor_start(e_y0, v.fast, m, run);
  for (int i = 0; i < m; i += 4) {
    v4d g = load4(run + i), ratio = load4(e_ry + i);
    const v4d a = load4(ay + i);
    const V vx4 = F::load(vx + i), vy4 = F::load(vy + i);
    for (int r = 0; r < rows; ++r) {
      if (r > 0) g *= ratio, ratio *= qy;
      const V gt = F::from(g), dy = F::from(ys[r] - a);
      const V wx = vx4 * gt, wy = vy4 * gt;
      F::store(row_of(W1, r, m) + i, wx);
      F::store(row_of(WB, r, m) + i, wy * dy);
      F::store(row_of(WB, rows + r, m) + i, wx * dy);
      F::store(row_of(WC, r, m) + i, wy * (1 + klt * dy * dy));
    }
  }
}
}  // namespace

SB_VECTOR_CLONES
void term_operands(const AxisFactors& e, const TermWeights<float>& v, const GridAxes& g, int m, float* X, float* W,
                   double* run) {
  term_operands_impl(e, v, g, m, X, W, run);
}

SB_VECTOR_CLONES
void term_operands(const AxisFactors& e, const TermWeights<double>& v, const GridAxes& g, int m, double* X, double* W,
                   double* run) {
  term_operands_impl(e, v, g, m, X, W, run);
}

SB_VECTOR_CLONES
void aniso_operands(const AxisFactors& e, const TermWeights<float>& v, const double* ax, const double* ay, double kl,
                    const GridAxes& g, int m, float* X3, float* W4, double* run) {
  aniso_operands_impl(e, v, ax, ay, kl, g, m, X3, W4, run);
}

SB_VECTOR_CLONES
void aniso_operands(const AxisFactors& e, const TermWeights<double>& v, const double* ax, const double* ay, double kl,
                    const GridAxes& g, int m, double* X3, double* W4, double* run) {
  aniso_operands_impl(e, v, ax, ay, kl, g, m, X3, W4, run);
}

namespace {
template <typename T>
struct Vec;
template <>
struct Vec<double> {
  using type = v4d;
  static constexpr int width = 4;
};
template <>
struct Vec<float> {
  using type = v8f;
  static constexpr int width = 8;
};
template <typename V, typename T>
[[gnu::always_inline]] inline V load(const T* p) {
  V v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

// A rows of W against three rows of X: 3A vector accumulators (A <= 4: twelve, with the three X vectors
// and one W vector, in sixteen registers), each point vector of X loaded once and used A times.
template <typename T, int A>
[[gnu::always_inline]] inline void block_sums(const T* w, const T* x, int mp, typename Vec<T>::type (&acc)[A][3]) {
  using V = typename Vec<T>::type;
  const T* x1 = x + mp;
  const T* x2 = x1 + mp;
  for (int i = 0; i < mp; i += Vec<T>::width) {
    const V b0 = load<V>(x + i), b1 = load<V>(x1 + i), b2 = load<V>(x2 + i);
    for (int k = 0; k < A; ++k) {
      const V ak = load<V>(w + static_cast<std::ptrdiff_t>(k) * mp + i);
      acc[k][0] += ak * b0;
      acc[k][1] += ak * b1;
      acc[k][2] += ak * b2;
    }
  }
}

// Sacc[(a + k) cols + c] += the sums of rows a..a+A-1 of W with every row c of X, as lane partial sums
// (Vec<T>::width values per output, 8 floats or 4 doubles): a caller that runs the product over chunks of points
// adds each chunk's vectors and sums the lanes once, at the end.
template <typename T, int A>
[[gnu::always_inline]] inline void add_row_block_acc(const T* Wt, int a, const T* Xt, int cols, int mp, T* Sacc) {
  using V = typename Vec<T>::type;
  constexpr int kLanes = Vec<T>::width;
  for (int c = 0; c < cols; c += 3) {
    V acc[A][3] = {};
    block_sums<T, A>(Wt + static_cast<std::ptrdiff_t>(a) * mp, Xt + static_cast<std::ptrdiff_t>(c) * mp, mp, acc);
    for (int k = 0; k < A; ++k)
      for (int d = 0; d < 3 && c + d < cols; ++d) {
        T* out = Sacc + kLanes * static_cast<std::ptrdiff_t>((a + k) * cols + c + d);
        const V sum = load<V>(out) + acc[k][d];
        std::memcpy(out, &sum, sizeof sum);
      }
  }
}

// Rows of W in blocks of four, the last one to three in a block of their own (no padding row multiplied):
// rows.template block<A>(a) for each. A member template, not a generic lambda: GCC compiles a lambda's
// call operator out of line for the baseline target, without the clone's AVX (it cost the double products
// a factor of three); an always_inline member template is inlined into each clone.
template <typename Rows>
[[gnu::always_inline]] inline void for_row_blocks(int nw, const Rows& rows) {
  int a = 0;
  for (; a + 4 <= nw; a += 4) rows.template block<4>(a);
  switch (nw - a) {
    case 3: rows.template block<3>(a); break;
    case 2: rows.template block<2>(a); break;
    case 1: rows.template block<1>(a); break;
    default: break;
  }
}

template <typename T>
struct ProductRowsAcc {
  const T *Wt, *Xt;
  int cols, mp;
  T* Sacc;
  template <int A>
  [[gnu::always_inline]] inline void block(int a) const {
    add_row_block_acc<T, A>(Wt, a, Xt, cols, mp, Sacc);
  }
};
}  // namespace

// Register-blocked 4 x 3: enough independent FMA chains to cover the FMA latency on two pipes.
SB_VECTOR_CLONES
void add_products_acc(const float* Wt, int nw, const float* Xt, int cols, int mp, float* Sacc) {
  for_row_blocks(nw, ProductRowsAcc<float>{Wt, Xt, cols, mp, Sacc});
}

SB_VECTOR_CLONES
void add_products_acc(const double* Wt, int nw, const double* Xt, int cols, int mp, double* Sacc) {
  for_row_blocks(nw, ProductRowsAcc<double>{Wt, Xt, cols, mp, Sacc});
}

namespace {
#pragma GCC diagnostic ignored "-Wpsabi"
// The horizontal add per 128-bit half: [a0+a1, a2+a3, b0+b1, b2+b3 | a4+a5, a6+a7, b4+b5, b6+b7].
// (__builtin_shufflevector: GCC >= 12 and Clang both have it; GCC's __builtin_shuffle is GCC's alone.)
[[gnu::always_inline]] inline v8f hadd(v8f a, v8f b) {
  return __builtin_shufflevector(a, b, 0, 2, 8, 10, 4, 6, 12, 14) +
         __builtin_shufflevector(a, b, 1, 3, 9, 11, 5, 7, 13, 15);
}
}  // namespace

// Eight rows of 8-lane partial sums to their eight totals: three levels of pairwise sums of neighbours
// (the horizontal add's butterfly), 7 vector adds where the lanes one by one take 56 scalar ones.
SB_VECTOR_CLONES
void lane_sums(const float* Sacc, int n, double* out) {
  int j = 0;
  for (; j + 8 <= n; j += 8) {
    v8f v[8];
    for (int k = 0; k < 8; ++k) v[k] = load<v8f>(Sacc + 8 * static_cast<std::ptrdiff_t>(j + k));
    const v8f ab = hadd(v[0], v[1]), cd = hadd(v[2], v[3]), ef = hadd(v[4], v[5]), gh = hadd(v[6], v[7]);
    const v8f abcd = hadd(ab, cd), efgh = hadd(ef, gh);  // [a b c d | a b c d] halves of the sums
    const v8f total = __builtin_shufflevector(abcd, efgh, 0, 1, 2, 3, 8, 9, 10, 11) +
                      __builtin_shufflevector(abcd, efgh, 4, 5, 6, 7, 12, 13, 14, 15);
    for (int k = 0; k < 8; ++k) out[j + k] = total[k];
  }
  for (; j < n; ++j) {
    double s = 0;
    for (int k = 0; k < 8; ++k) s += Sacc[8 * static_cast<std::ptrdiff_t>(j) + k];
    out[j] = s;
  }
}

void lane_sums(const double* Sacc, int n, double* out) {
  for (int j = 0; j < n; ++j) {
    const double* p = Sacc + 4 * static_cast<std::ptrdiff_t>(j);
    out[j] = (p[0] + p[1]) + (p[2] + p[3]);
  }
}

SB_VECTOR_CLONES
void scattered_exponents(const double* mx, const double* my, const double* mz, int nm, const double* a, double lambda,
                         double min_exponent, double* g) {
  const double ax = a[0], ay = a[1], az = a[2];
  SB_IVDEP
  for (int j = 0; j < nm; ++j) {
    const double dx = mx[j] - ax, dy = my[j] - ay, dz = mz[j] - az;
    g[j] = max2(-lambda * (dx * dx + dy * dy + dz * dz), min_exponent);
  }
}

SB_VECTOR_CLONES
void scattered_add(const double* mx, const double* my, int nm, const double* a, const double* v, double kl,
                   const double* g, const ScatteredSums& s) {
  const double ax = a[0], ay = a[1], vx = v[0], vy = v[1], vw = v[2];
  double* sx = s.x;
  double* sy = s.y;
  if (kl == 0) {
    SB_IVDEP
    for (int j = 0; j < nm; ++j) {
      sx[j] += vx * g[j];
      sy[j] += vy * g[j];
    }
  } else {
    SB_IVDEP
    for (int j = 0; j < nm; ++j) {
      const double dx = mx[j] - ax, dy = my[j] - ay;
      const double along = kl * (dx * vx + dy * vy);
      sx[j] += (vx + along * dx) * g[j];
      sy[j] += (vy + along * dy) * g[j];
    }
  }
  if (s.w == nullptr) return;
  double* sw = s.w;
  SB_IVDEP
  for (int j = 0; j < nm; ++j) sw[j] += vw * g[j];
}

// Blocks of 8 markers held in four vector accumulators while the inside markers stream past: each
// output is stored once, and the kernel rows are read once per block.
SB_VECTOR_CLONES
void dilation_sum(const double* Kx, const double* Ky, int stride, const int* ks, const double* h, int nk, double* dx,
                  double* dy) {
  for (int j = 0; j < stride; j += 8) {
    v4d x0 = {}, x1 = {}, y0 = {}, y1 = {};
    for (int q = 0; q < nk; ++q) {
      const std::ptrdiff_t row = static_cast<std::ptrdiff_t>(ks[q]) * stride + j;
      const double hq = h[q];
      x0 += hq * load4(Kx + row);
      x1 += hq * load4(Kx + row + 4);
      y0 += hq * load4(Ky + row);
      y1 += hq * load4(Ky + row + 4);
    }
    std::memcpy(dx + j, &x0, sizeof x0);
    std::memcpy(dx + j + 4, &x1, sizeof x1);
    std::memcpy(dy + j, &y0, sizeof y0);
    std::memcpy(dy + j + 4, &y1, sizeof y1);
  }
}

}  // namespace sb::hydroshear_kernels
