#include "core/models/hydroshear_kernels.hpp"

#include <cmath>
#include <cstring>
#include <type_traits>

#include "core/base/vector_clones.hpp"

namespace sb::hydroshear_kernels {

// Selects instead of std::max / branches: the loops stay branch-free, so they vectorise.
namespace {
inline double relu(double v) { return v > 0 ? v : 0.0; }
inline double max2(double a, double b) { return a > b ? a : b; }
}  // namespace

SB_VECTOR_CLONES
void transform_points(const double* r, const double* t, const double* x, const double* y, const double* z, int n,
                      double* ox, double* oy, double* oz) {
  const double r0 = r[0], r1 = r[1], r2 = r[2], r3 = r[3], r4 = r[4], r5 = r[5], r6 = r[6], r7 = r[7], r8 = r[8];
  const double t0 = t[0], t1 = t[1], t2 = t[2];
#pragma GCC ivdep
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
#pragma GCC ivdep
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
#pragma GCC ivdep
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
// The loop of shear_operands for one weight choice: a select on a loop-invariant bool stops GCC's
// vectoriser, two instantiations do not.
template <bool kWeightPaper, bool kNormalZ>
[[gnu::always_inline]] inline void shear_operands_loop(const ShearColumns& c, const ShearConstants& k, int n,
                                                       double* vx, double* vy, double* lead, double* rx, double* ry,
                                                       std::uint8_t* fast) {
  const double l = k.lambda_s;
#pragma GCC ivdep
  for (int i = 0; i < n; ++i) {
    const double u_n = c.un[i];
    const double nx = kNormalZ ? 0.0 : c.nx[i], ny = kNormalZ ? 0.0 : c.ny[i];
    const double fx = k.E * u_n * nx + k.K * (c.ux[i] - u_n * nx);
    const double fy = k.E * u_n * ny + k.K * (c.uy[i] - u_n * ny);
    const double w = kWeightPaper ? -c.phi[i] : k.E * u_n;
    vx[i] = -w * fx;
    vy[i] = -w * fy;
    const double ax = c.px[i] + c.ux[i] + k.shift_x, ay = c.py[i] + c.uy[i] + k.shift_y, az = c.pz[i] + c.uz[i];
    const double dx0 = k.x0 - ax, dxn = k.xn - ax, dy0 = k.y0 - ay, dyn = k.yn - ay, dz = k.z0 - az;
    const double lz = l * dz * dz;
    const double worst = l * max2(dx0 * dx0, dxn * dxn) + l * max2(dy0 * dy0, dyn * dyn) + lz;
    const bool ok = worst <= k.max_total_exponent;
    lead[i] = ok ? -l * dx0 * dx0 - l * dy0 * dy0 - lz : 0.0;
    rx[i] = ok ? -l * (k.hx * k.hx + 2 * k.hx * dx0) : 0.0;
    ry[i] = ok ? -l * (k.hy * k.hy + 2 * k.hy * dy0) : 0.0;
    fast[i] = ok ? 1 : 0;
  }
}
}  // namespace

SB_VECTOR_CLONES
void shear_operands(const ShearColumns& in, const ShearConstants& constants, int n, double* vx, double* vy,
                    double* lead, double* rx, double* ry, std::uint8_t* fast) {
  // Local copies: the compiler cannot prove that the outputs do not alias a referenced struct.
  const ShearColumns c = in;
  const ShearConstants k = constants;
  if (k.weight_paper)
    k.normal_z ? shear_operands_loop<true, true>(c, k, n, vx, vy, lead, rx, ry, fast)
               : shear_operands_loop<true, false>(c, k, n, vx, vy, lead, rx, ry, fast);
  else
    k.normal_z ? shear_operands_loop<false, true>(c, k, n, vx, vy, lead, rx, ry, fast)
               : shear_operands_loop<false, false>(c, k, n, vx, vy, lead, rx, ry, fast);
}

namespace {
// Rows 1..n-1 of a block from its row 0: row k = row k-1 * r_i q^(k-1), the ratio recurrence of GaussianAxis
// carried across rows (each row one vectorised pass over the points).
[[gnu::always_inline]] inline void ratio_recurrence(double* block, const double* e_r, int mp, int n, double q) {
  double q_pow = 1.0;
  for (int k = 1; k < n; ++k) {
    const double* prev = block + static_cast<std::ptrdiff_t>(k - 1) * mp;
    double* row = block + static_cast<std::ptrdiff_t>(k) * mp;
#pragma GCC ivdep
    for (int i = 0; i < mp; ++i) row[i] = prev[i] * (e_r[i] * q_pow);
    q_pow *= q;
  }
}
}  // namespace

SB_VECTOR_CLONES
void weight_block(const double* e_ry, const double* w, const std::uint8_t* fast, int mp, int rows, double qy,
                  double* block) {
#pragma GCC ivdep
  for (int i = 0; i < mp; ++i) {
    const double x = w[i];  // loaded unconditionally: a conditional load stops vectorisation
    block[i] = fast[i] ? x : 0.0;
  }
  ratio_recurrence(block, e_ry, mp, rows, qy);
}

SB_VECTOR_CLONES
void shear_matrices(const double* e_lead, const double* e_rx, const double* e_ry, const double* vx, const double* vy,
                    const std::uint8_t* fast, int mp, int rows, int cols, double qx, double qy, double* Xt,
                    double* Wt, const double* vw) {
  // Xt: row 0 = E_i, row c = row c-1 * r_i q^(c-1), the ratio recurrence of GaussianAxis carried
  // across rows (each row is one vectorised pass over the points).
  for (int i = 0; i < mp; ++i) Xt[i] = e_lead[i];
  ratio_recurrence(Xt, e_rx, mp, cols, qx);
  const int cols_pad = (cols + 2) / 3 * 3;
  std::memset(Xt + static_cast<std::ptrdiff_t>(cols) * mp, 0, sizeof(double) * mp * (cols_pad - cols));
  // Wt: rows 0 = (fast) vx_i and vy_i, then the y axis' recurrence applied to both.
  double* wx0 = Wt;
  double* wy0 = Wt + static_cast<std::ptrdiff_t>(rows) * mp;
#pragma GCC ivdep
  for (int i = 0; i < mp; ++i) {
    const double x = vx[i], y = vy[i];  // loaded unconditionally: a conditional load stops vectorisation
    wx0[i] = fast[i] ? x : 0.0;
    wy0[i] = fast[i] ? y : 0.0;
  }
  double q_pow = 1.0;
  for (int r = 1; r < rows; ++r) {
    const double* px = wx0 + static_cast<std::ptrdiff_t>(r - 1) * mp;
    const double* py = wy0 + static_cast<std::ptrdiff_t>(r - 1) * mp;
    double* rx = wx0 + static_cast<std::ptrdiff_t>(r) * mp;
    double* ry = wy0 + static_cast<std::ptrdiff_t>(r) * mp;
#pragma GCC ivdep
    for (int i = 0; i < mp; ++i) {
      const double ratio = e_ry[i] * q_pow;
      rx[i] = px[i] * ratio;
      ry[i] = py[i] * ratio;
    }
    q_pow *= qy;
  }
  // The weights' block, the same recurrence.
  if (vw != nullptr) weight_block(e_ry, vw, fast, mp, rows, qy, Wt + static_cast<std::ptrdiff_t>(2 * rows) * mp);
  const int nw = (vw != nullptr ? 3 : 2) * rows, nw_pad = (nw + 2) / 3 * 3;
  std::memset(Wt + static_cast<std::ptrdiff_t>(nw) * mp, 0, sizeof(double) * mp * (nw_pad - nw));
}

SB_VECTOR_CLONES
void aniso_operands(const double* e_lead, const double* e_rx, const double* e_ry, const double* vx, const double* vy,
                    const std::uint8_t* fast, const double* ax, const double* ay, const double* xs, const double* ys,
                    int rows, int cols, int mp, double qx, double qy, double kl, float* X3, float* W4, double* Yd) {
  const auto row = [mp](float* m, int r) { return m + static_cast<std::ptrdiff_t>(r) * mp; };
  const int cols_pad = (cols + 2) / 3 * 3;
  float* XC = X3;
  float* XA = row(X3, cols_pad);
  float* XB = row(X3, 2 * cols_pad);
  // The x factor E_i X_i[c] (its ratio recurrence in double: Xd holds the running row) and its variants.
  double* Xd = Yd;
  for (int i = 0; i < mp; ++i) Xd[i] = e_lead[i];
  // One step of an axis' ratio recurrence on the running row (the k-th step multiplies by r_i q^(k-1)).
  const auto step = [mp](double* run, const double* e_r, double& q_pow, double q) {
#pragma GCC ivdep
    for (int i = 0; i < mp; ++i) run[i] *= e_r[i] * q_pow;
    q_pow *= q;
  };
  double q_pow = 1.0;
  for (int c = 0; c < cols; ++c) {
    if (c > 0) step(Xd, e_rx, q_pow, qx);
    float* xc = row(XC, c);
    float* xa = row(XA, c);
    float* xb = row(XB, c);
    const double X = xs[c];
    const float klf = static_cast<float>(kl);
#pragma GCC ivdep
    for (int i = 0; i < mp; ++i) {   // the variants in float: the operands are rounded to float anyway
      const float e = static_cast<float>(Xd[i]), dx = static_cast<float>(X - ax[i]);
      xc[i] = e;
      xa[i] = e * (1 + klf * dx * dx);
      xb[i] = e * dx;
    }
  }
  for (int c = cols; c < cols_pad; ++c)
    for (float* m : {XC, XA, XB}) std::memset(row(m, c), 0, sizeof(float) * mp);
  // The weights: W1 = vx Y, WB = [vy Y dy ; vx Y dy], WC = vy Y (1 + kl dy^2), with Yd the running row of
  // fast_i Y_i[r] (its recurrence, as shear_matrices').
  float* W1 = W4;
  float* WB = row(W4, rows);
  float* WC = row(W4, 3 * rows);
  double* Yrun = Yd;
  for (int i = 0; i < mp; ++i) Yrun[i] = fast[i] ? 1.0 : 0.0;
  q_pow = 1.0;
  for (int r = 0; r < rows; ++r) {
    if (r > 0) step(Yrun, e_ry, q_pow, qy);
    float* w1 = row(W1, r);
    float* by = row(WB, r);
    float* bx = row(WB, rows + r);
    float* wc = row(WC, r);
    const double Y = ys[r];
    const float klf = static_cast<float>(kl);
#pragma GCC ivdep
    for (int i = 0; i < mp; ++i) {
      const float dy = static_cast<float>(Y - ay[i]), wx = static_cast<float>(vx[i] * Yrun[i]),
                  wy = static_cast<float>(vy[i] * Yrun[i]);
      w1[i] = wx;
      by[i] = wy * dy;
      bx[i] = wx * dy;
      wc[i] = wy * (1 + klf * dy * dy);
    }
  }
}

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
template <typename T> struct Vec;
template <> struct Vec<double> { using type = v4d; static constexpr int width = 4; };
template <> struct Vec<float> { using type = v8f; static constexpr int width = 8; };
template <typename V, typename T>
[[gnu::always_inline]] inline V load(const T* p) {
  V v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
template <typename V>
[[gnu::always_inline]] inline double lane_sum(V v) {
  double s = 0;
  for (int k = 0; k < static_cast<int>(sizeof(V) / sizeof(v[0])); ++k) s += v[k];
  return s;
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

// S[(a + k) cols + c] += the sums of rows a..a+A-1 of W with every row c of X (lanes added up).
template <int A>
[[gnu::always_inline]] inline void add_row_block(const double* Wt, int a, const double* Xt, int cols, int mp,
                                                 double* S) {
  for (int c = 0; c < cols; c += 3) {
    v4d acc[A][3] = {};
    block_sums<double, A>(Wt + static_cast<std::ptrdiff_t>(a) * mp, Xt + static_cast<std::ptrdiff_t>(c) * mp, mp, acc);
    for (int k = 0; k < A; ++k)
      for (int d = 0; d < 3 && c + d < cols; ++d) S[(a + k) * cols + c + d] += lane_sum(acc[k][d]);
  }
}

// Single precision, accumulated into 8-lane partial sums (Sacc: 8 floats per output): a caller that runs the
// product over chunks of points adds each chunk's vectors and sums the lanes once, at the end.
template <int A>
[[gnu::always_inline]] inline void add_row_block_acc(const float* Wt, int a, const float* Xt, int cols, int mp,
                                                     float* Sacc) {
  for (int c = 0; c < cols; c += 3) {
    v8f acc[A][3] = {};
    block_sums<float, A>(Wt + static_cast<std::ptrdiff_t>(a) * mp, Xt + static_cast<std::ptrdiff_t>(c) * mp, mp, acc);
    for (int k = 0; k < A; ++k)
      for (int d = 0; d < 3 && c + d < cols; ++d) {
        float* out = Sacc + 8 * static_cast<std::ptrdiff_t>((a + k) * cols + c + d);
        const v8f sum = load<v8f>(out) + acc[k][d];
        std::memcpy(out, &sum, sizeof sum);
      }
  }
}

// Rows of W in blocks of four, the last one to three in a block of their own (no padding row multiplied):
// block(std::integral_constant<int, A>, a) for each.
template <typename Block>
[[gnu::always_inline]] inline void for_row_blocks(int nw, Block block) {
  int a = 0;
  for (; a + 4 <= nw; a += 4) block(std::integral_constant<int, 4>{}, a);
  switch (nw - a) {
    case 3: block(std::integral_constant<int, 3>{}, a); break;
    case 2: block(std::integral_constant<int, 2>{}, a); break;
    case 1: block(std::integral_constant<int, 1>{}, a); break;
    default: break;
  }
}
}  // namespace

// Register-blocked 4 x 3: enough independent FMA chains to cover the FMA latency on two pipes.
SB_VECTOR_CLONES
void add_products_nt(const double* Wt, int nw, const double* Xt, int cols, int mp, double* S) {
  // The lambdas are inlined (always_inline), so each clone's loops are compiled for its own target.
  for_row_blocks(nw, [&](auto A, int a) [[gnu::always_inline]] { add_row_block<decltype(A)::value>(Wt, a, Xt, cols, mp, S); });
}

SB_VECTOR_CLONES
void add_products_acc(const float* Wt, int nw, const float* Xt, int cols, int mp, float* Sacc) {
  for_row_blocks(nw, [&](auto A, int a) [[gnu::always_inline]] { add_row_block_acc<decltype(A)::value>(Wt, a, Xt, cols, mp, Sacc); });
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
