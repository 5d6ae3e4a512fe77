#include "core/models/hydroshear_kernels.hpp"

#include <cmath>
#include <cstring>

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
[[gnu::always_inline]] inline double hsum(v4d v) { return (v[0] + v[1]) + (v[2] + v[3]); }
}  // namespace

// Register-blocked 3 x 3: nine vector accumulators, enough independent FMA chains to cover the FMA
// latency on two pipes; each point vector of W and X is loaded once per block and used three times.
SB_VECTOR_CLONES
void add_products_nt(const double* Wt, int nw, const double* Xt, int cols, int mp, double* S) {
  for (int a = 0; a < nw; a += 3) {
    const double* w0 = Wt + static_cast<std::ptrdiff_t>(a) * mp;
    const double* w1 = w0 + mp;
    const double* w2 = w1 + mp;
    for (int c = 0; c < cols; c += 3) {
      const double* x0 = Xt + static_cast<std::ptrdiff_t>(c) * mp;
      const double* x1 = x0 + mp;
      const double* x2 = x1 + mp;
      v4d s00 = {}, s01 = {}, s02 = {}, s10 = {}, s11 = {}, s12 = {}, s20 = {}, s21 = {}, s22 = {};
      for (int i = 0; i < mp; i += 4) {
        const v4d a0 = load4(w0 + i), a1 = load4(w1 + i), a2 = load4(w2 + i);
        const v4d b0 = load4(x0 + i), b1 = load4(x1 + i), b2 = load4(x2 + i);
        s00 += a0 * b0;
        s01 += a0 * b1;
        s02 += a0 * b2;
        s10 += a1 * b0;
        s11 += a1 * b1;
        s12 += a1 * b2;
        s20 += a2 * b0;
        s21 += a2 * b1;
        s22 += a2 * b2;
      }
      const double out[3][3] = {{hsum(s00), hsum(s01), hsum(s02)},
                                {hsum(s10), hsum(s11), hsum(s12)},
                                {hsum(s20), hsum(s21), hsum(s22)}};
      for (int da = 0; da < 3 && a + da < nw; ++da)
        for (int dc = 0; dc < 3 && c + dc < cols; ++dc) S[(a + da) * cols + c + dc] += out[da][dc];
    }
  }
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
