#pragma once
// HydroShear's per-point arithmetic over structure-of-arrays columns: straight-line loops with no
// branches and no cross-iteration state, so the compiler vectorises them across points, each compiled
// for AVX2/FMA and the baseline (core/base/vector_clones.hpp). HydroShearBatch gathers the points of one
// slot into columns, calls these, and scatters the result; the equations are in core/models/hydroshear.hpp.
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

// The shear sum's per-point operands on a uniform marker grid (see HydroShearBatch::shear_sum):
// (vx, vy) = -w f^xy, and the three exponents of the factored Gaussian of the anchor a = p + u:
// lead = -l (x0 - a_x)^2 - l (y0 - a_y)^2 - l (z0 - a_z)^2, rx, ry the axes' ratio exponents.
// fast[i] = 0 when a partial product could come near underflow (the caller sums that point another
// way); its exponents are then 0 and its weight must not be used.
struct ShearColumns {
  const double *px, *py, *pz;       // the real point o_i (the anchor is o_i + u_i)
  const double *ux, *uy, *uz, *un;  // state
  const double* phi;                // phi_E used by the paper's weight
  const double *nx, *ny, *nz;       // split normal (not read when normal_z)
};
struct ShearConstants {
  double E, K, lambda_s, z0;
  bool weight_paper;
  bool normal_z;                  // n = +z for every point
  double x0, xn, hx, y0, yn, hy;  // the grid axes' first and last coordinates and pitches
  double max_total_exponent;
  double shift_x = 0, shift_y = 0;  // added to every anchor (the contact-following shift)
};
void shear_operands(const ShearColumns& in, const ShearConstants& k, int n, double* vx, double* vy, double* lead,
                    double* rx, double* ry, std::uint8_t* fast);

// From exp(lead), exp(rx), exp(ry) (already exponentiated) the transposed operands of the sum, with
// the point's E_i = exp(lead) folded into X and its weight into W:
//   Xt[c * mp + i] = E_i X_i[c]            (X_i[c] the ratio recurrence of GaussianAxis, X_i[0] = 1)
//   Wt[r * mp + i] = fast_i vx_i Y_i[r],  Wt[(rows + r) * mp + i] = fast_i vy_i Y_i[r]
// so that sum_i Wt[r] Xt[c] = sum_i vx_i exp(-l |m_rc - a_i|^2). For i < mp (points past n must have
// zero weight and finite exponents); qx, qy: the axes' constants. Zeroes the padding rows that
// add_products_nt reads.
// With vw (not null) a third block of rows, Wt[(2 rows + r) * mp + i] = fast_i vw_i Y_i[r], sums the
// weights alone (the stick saturation's denominator); Wt must then hold round_up(3 rows, 3) rows.
void shear_matrices(const double* e_lead, const double* e_rx, const double* e_ry, const double* vx, const double* vy,
                    const std::uint8_t* fast, int mp, int rows, int cols, double qx, double qy, double* Xt, double* Wt,
                    const double* vw = nullptr);

// One more block of rows of Wt for another weight column: block[r * mp + i] = fast_i w_i Y_i[r] (the same
// recurrence as shear_matrices' blocks, so it pairs with the Xt that shear_matrices built).
void weight_block(const double* e_ry, const double* w, const std::uint8_t* fast, int mp, int rows, double qy,
                  double* block);

// The shared-operand path (the contact variant, HydroShearBatch::shear_sum_shared): the point operands
// shared by every Gaussian term, once per step: v = -w f^xy, the weight w and the anchor a = o + u + shift.
void point_operands(const ShearColumns& in, const ShearConstants& k, int n, double* vx, double* vy, double* w,
                    double* ax, double* ay, double* az);

// One term's exponents with the Gaussian split by axis, each factor at most 1 (so single precision holds
// it without overflow): G_i(r, c) = (gx0_i X_i[c]) (gy0_i Y_i[r]) with
//   ex0 = -l (x0 - a_x)^2 - l (z0 - a_z)^2,  ey0 = -l (y0 - a_y)^2,  rx, ry the axes' ratio exponents.
// The recurrences run in double from gx0, gy0: fast[i] = 0 (exponents 0) when either axis' factor could
// come near underflow there (l d^2 past k.max_total_exponent on its farthest marker).
// Returns the number of points that are not fast.
int axis_exponents(const double* ax, const double* ay, const double* az, const ShearConstants& k, int n, double* ex0,
                   double* rx, double* ey0, double* ry, std::uint8_t* fast);

// An isotropic term's operands (in float or in double) for a chunk of m points (a multiple of 8), from the
// exponentials of axis_exponents:
//   X[c * m + i] = gx0_i X_i[c]  (round_up(cols, 3) rows, the padding rows zeroed)
//   W[r * m + i] = fast vx gy0 Y_i[r],  W[(rows + r) * m + i] = fast vy gy0 Y_i[r]
//   and with w (not null) W[(2 rows + r) * m + i] = fast w gy0 Y_i[r] (the stick saturation's weights).
// run: m doubles of scratch (the recurrences' running row, in double).
void term_operands(const double* e_x0, const double* e_rx, const double* e_y0, const double* e_ry, const float* vx,
                   const float* vy, const float* w, const std::uint8_t* fast, int rows, int cols, int m, double qx,
                   double qy, float* X, float* W, double* run);
void term_operands(const double* e_x0, const double* e_rx, const double* e_y0, const double* e_ry, const double* vx,
                   const double* vy, const double* w, const std::uint8_t* fast, int rows, int cols, int m, double qx,
                   double qy, double* X, double* W, double* run);

// The anisotropic term's operands in float or double (the factor 1 + k l d d^T; dx = xs[c] - ax_i,
// dy = ys[r] - ay_i; ax, ay finite for every i < m), from the exponentials of axis_exponents:
//   X3 = [XC; XA; XB], each round_up(cols, 3) rows (padding rows zeroed):
//        XC[c] = gx0 X_i[c],  XA[c] = XC[c] (1 + kl dx^2),  XB[c] = XC[c] dx
//   W4 = [W1; WB; WC], 4 rows rows, with Yg[r] = fast gy0 Y_i[r]:
//        W1[r] = vx Yg[r],  WB[r] = vy Yg[r] dy,  WB[rows + r] = vx Yg[r] dy,  WC[r] = vy Yg[r] (1 + kl dy^2)
// run: m doubles of scratch.
void aniso_operands(const double* e_x0, const double* e_rx, const double* e_y0, const double* e_ry, const float* vx,
                    const float* vy, const std::uint8_t* fast, const double* ax, const double* ay, const double* xs,
                    const double* ys, int rows, int cols, int m, double qx, double qy, double kl, float* X3, float* W4,
                    double* run);
void aniso_operands(const double* e_x0, const double* e_rx, const double* e_y0, const double* e_ry, const double* vx,
                    const double* vy, const std::uint8_t* fast, const double* ax, const double* ay, const double* xs,
                    const double* ys, int rows, int cols, int m, double qx, double qy, double kl, double* X3,
                    double* W4, double* run);

// S[a * cols + c] += sum_{i < mp} Wt[a * mp + i] Xt[c * mp + i] for a < nw, c < cols. mp a multiple of
// 4; Wt must hold round_up(nw, 3) rows and Xt round_up(cols, 3) rows (the extra rows zero).
void add_products_nt(const double* Wt, int nw, const double* Xt, int cols, int mp, double* S);
// The same in single precision into 8-lane partial sums: Sacc[8 (a * cols + c) + k] += lane k of the sum
// (the lanes' total is the product), mp a multiple of 8. For products run over chunks of points.
void add_products_acc(const float* Wt, int nw, const float* Xt, int cols, int mp, float* Sacc);
// The same in double into 4-lane partial sums (Sacc: 4 doubles per output), mp a multiple of 4.
void add_products_acc(const double* Wt, int nw, const double* Xt, int cols, int mp, double* Sacc);

// out[j] = the sum of the 8 lanes of Sacc[8 j .. 8 j + 7], j < n (add_products_acc's partial sums).
void lane_sums(const float* Sacc, int n, double* out);
// out[j] = the sum of the 4 lanes of Sacc[4 j .. 4 j + 3] (the double add_products_acc's partial sums).
void lane_sums(const double* Sacc, int n, double* out);

// The dilation's sums over the markers inside the indenter: d[j] = sum_q h[q] K[ks[q] * stride + j] for
// j < stride, for both axes (Kx, Ky k-major, rows padded with zeros to dilation_stride(markers)).
inline int dilation_stride(int markers) { return (markers + 7) / 8 * 8; }
void dilation_sum(const double* Kx, const double* Ky, int stride, const int* ks, const double* h, int nk, double* dx,
                  double* dy);

}  // namespace sb::hydroshear_kernels
