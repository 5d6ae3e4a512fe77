#pragma once
// HydroShear's per-point arithmetic over structure-of-arrays columns: straight-line loops with no
// branches and no cross-iteration state, so the compiler vectorises them across points, each compiled
// for AVX2/FMA and the baseline (core/base/vector_clones.hpp). The step's phases (hydroshear_step.hpp) gather
// the points of one slot into columns and call these; the equations are in core/models/hydroshear.hpp.
// tests/test_model_kernels.cpp checks the whole batch against a dense per-point reference loop.
#include <cstdint>

#include "core/models/model_common.hpp"

namespace sb::hydroshear_kernels {

// p_E = X * p (X: rotation R row-major r[9], translation t[3]), for n points.
void transform_points(const double* r, const double* t, const double* x, const double* y, const double* z, int n,
                      double* ox, double* oy, double* oz);

// phi[i] = pad.value(p_i + shift), the box distance of FlatPad::value without its branch.
void flat_pad_phi(const FlatPad& pad, const double* shift, const double* x, const double* y, const double* z, int n,
                  double* phi);

// One tracker step per point from (s_prev, q) to (s, p) with old state o, split along n (unit); cone =
// mu E / K. Writes u (metres), u_n and slip (1: clipped to the cone, 0: stick). normal_z: n = +z for
// every point (the authors' split) and the n columns are not read.
struct AdvanceColumns {
  const double *s_prev, *qx, *qy, *qz;  // phi_E and position at the previous pose
  const double *s, *px, *py, *pz;       // now (s < 0: the caller passes only points in the gel)
  const double *ox, *oy, *oz;           // old state (0 for a point that enters)
  const double *nx, *ny, *nz;           // split normal, out of the gel
};
void advance_points(const AdvanceColumns& in, bool normal_z, double cone, int n, double* ux, double* uy, double* uz,
                    double* un, std::uint8_t* slip);

// The shear sum (core/models/hydroshear_shear.cpp), in four kernels. Once per step, the operands every Gaussian
// term shares (point_operands). Per term, its Gaussian split by axis into factors of at most 1 (axis_exponents,
// then exp_in_place); per chunk of points, the term's operands in float or double built from them (term_operands,
// aniso_operands) and their products summed into lane partial sums (add_products_acc, then lane_sums).
struct ShearColumns {
  const double *px, *py, *pz;       // the real point o_i (the anchor is o_i + u_i)
  const double *ux, *uy, *uz, *un;  // state
  const double* phi;                // phi_E used by the paper's weight
  const double *nx, *ny, *nz;       // split normal (not read when normal_z)
};
struct PointConstants {
  double E, K;
  bool weight_paper;
  bool normal_z;                    // n = +z for every point
  double shift_x = 0, shift_y = 0;  // added to every anchor (the contact-following shift)
};
struct PointOperands {
  double *vx, *vy, *w;   // v = -w f^xy and the weight w
  double *ax, *ay, *az;  // the anchor a = o + u + shift
};
void point_operands(const ShearColumns& in, const PointConstants& k, int n, const PointOperands& out);

// One term's Gaussian and the grid's axes.
struct AxisConstants {
  double lambda, z0;
  double x0, xn, hx, y0, yn, hy;  // the grid axes' first and last coordinates and pitches
  double max_total_exponent;
};
// One term's per-point factors split by axis, G_i(r, c) = (gx0_i X_i[c]) (gy0_i Y_i[r]): axis_exponents writes
// the exponents (AxisExponents), exp_in_place turns them into the factors the operand builders read (AxisFactors).
//   x0 = -l (x0 - a_x)^2 - l (z0 - a_z)^2,  y0 = -l (y0 - a_y)^2,  rx, ry the axes' ratio exponents.
template <typename P>
struct AxisColumns {
  P *x0, *rx, *y0, *ry;
  AxisColumns at(int off) const { return {x0 + off, rx + off, y0 + off, ry + off}; }
};
using AxisExponents = AxisColumns<double>;
using AxisFactors = AxisColumns<const double>;
// The recurrences run in double from gx0, gy0: fast[i] = 0 (exponents 0) when either axis' factor could come near
// underflow there (l d^2 past k.max_total_exponent on its farthest marker). Returns the number of points that are
// not fast.
int axis_exponents(const double* ax, const double* ay, const double* az, const AxisConstants& k, int n,
                   const AxisExponents& out, std::uint8_t* fast);

// The marker grid as the operand builders read it: its shape, the axes' recurrence constants q, its coordinates.
struct GridAxes {
  int rows, cols;
  double qx, qy;
  const double *xs, *ys;
};
// A term's per-point weights in the products' precision; w may be null (no weights block).
template <typename T>
struct TermWeights {
  const T *vx, *vy, *w;
  const std::uint8_t* fast;
  TermWeights at(int off) const { return {vx + off, vy + off, w != nullptr ? w + off : nullptr, fast + off}; }
};

// An isotropic term's operands (in float or in double) for a chunk of m points (a multiple of 8):
//   X[c * m + i] = gx0_i X_i[c]  (round_up(cols, 3) rows, the padding rows zeroed)
//   W[r * m + i] = fast vx gy0 Y_i[r],  W[(rows + r) * m + i] = fast vy gy0 Y_i[r]
//   and with w (not null) W[(2 rows + r) * m + i] = fast w gy0 Y_i[r] (the stick saturation's weights).
// run: m doubles of scratch (the recurrences' running row, in double).
void term_operands(const AxisFactors& e, const TermWeights<float>& v, const GridAxes& g, int m, float* X, float* W,
                   double* run);
void term_operands(const AxisFactors& e, const TermWeights<double>& v, const GridAxes& g, int m, double* X, double* W,
                   double* run);

// The anisotropic term's operands in float or double (the factor 1 + kl d d^T; dx = xs[c] - ax_i,
// dy = ys[r] - ay_i; ax, ay finite for every i < m):
//   X3 = [XC; XA; XB], each round_up(cols, 3) rows (padding rows zeroed):
//        XC[c] = gx0 X_i[c],  XA[c] = XC[c] (1 + kl dx^2),  XB[c] = XC[c] dx
//   W4 = [W1; WB; WC], 4 rows rows, with Yg[r] = fast gy0 Y_i[r]:
//        W1[r] = vx Yg[r],  WB[r] = vy Yg[r] dy,  WB[rows + r] = vx Yg[r] dy,  WC[r] = vy Yg[r] (1 + kl dy^2)
// run: m doubles of scratch.
void aniso_operands(const AxisFactors& e, const TermWeights<float>& v, const double* ax, const double* ay, double kl,
                    const GridAxes& g, int m, float* X3, float* W4, double* run);
void aniso_operands(const AxisFactors& e, const TermWeights<double>& v, const double* ax, const double* ay, double kl,
                    const GridAxes& g, int m, double* X3, double* W4, double* run);

// Sacc[8 (a * cols + c) + k] += lane k of sum_{i < mp} Wt[a * mp + i] Xt[c * mp + i] for a < nw, c < cols, in
// single precision into 8-lane partial sums (the lanes' total is the product), mp a multiple of 8: products run
// over chunks of points add each chunk's lanes. Wt must hold round_up(nw, 3) rows and Xt round_up(cols, 3) rows
// (the extra rows zero).
void add_products_acc(const float* Wt, int nw, const float* Xt, int cols, int mp, float* Sacc);
// The same in double into 4-lane partial sums (Sacc: 4 doubles per output), mp a multiple of 4.
void add_products_acc(const double* Wt, int nw, const double* Xt, int cols, int mp, double* Sacc);

// out[j] = the sum of the 8 lanes of Sacc[8 j .. 8 j + 7], j < n (add_products_acc's partial sums).
void lane_sums(const float* Sacc, int n, double* out);
// out[j] = the sum of the 4 lanes of Sacc[4 j .. 4 j + 3] (the double add_products_acc's partial sums).
void lane_sums(const double* Sacc, int n, double* out);

// The shear sum off a grid (markers anywhere: the TacTip's pins on its dome), one point a at a time against every
// marker m_j held as columns mx, my, mz: the term's exponents (scattered_exponents), exp_in_place, then the
// point's share (scattered_add). Markers in columns and the branches out of the loops, so both vectorise.
//   g[j] = max(-lambda |m_j - a|^2, min_exponent)
void scattered_exponents(const double* mx, const double* my, const double* mz, int nm, const double* a, double lambda,
                         double min_exponent, double* g);
// The sums one point adds to: x, y per marker and w (may be null: no stick saturation).
struct ScatteredSums {
  double *x, *y, *w;
};
//   s_j += (v + kl d_j (d_j . v)) g[j] with d_j = (mx_j - a_x, my_j - a_y), v = (v[0], v[1]) (the anisotropic
//   term's factor 1 + kl d d^T; kl = 0: isotropic), and w_j += v[2] g[j].
void scattered_add(const double* mx, const double* my, int nm, const double* a, const double* v, double kl,
                   const double* g, const ScatteredSums& s);

// The dilation's sums over the markers inside the indenter: d[j] = sum_q h[q] K[ks[q] * stride + j] for
// j < stride, for both axes (Kx, Ky k-major, rows padded with zeros to dilation_stride(markers)).
inline int dilation_stride(int markers) { return (markers + 7) / 8 * 8; }
void dilation_sum(const double* Kx, const double* Ky, int stride, const int* ks, const double* h, int nk, double* dx,
                  double* dy);

}  // namespace sb::hydroshear_kernels
