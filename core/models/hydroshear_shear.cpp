// HydroShear's phase 3, the shear sum (core/models/hydroshear_step.hpp): M_s before kappa_s at every marker.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <span>
#include <type_traits>
#include <utility>

#include "core/models/hydroshear_kernels.hpp"
#include "core/models/hydroshear_step.hpp"

namespace sb::hydroshear {

namespace kernels = hydroshear_kernels;

namespace {

constexpr double kMinExponent = -700;  // exp_in_place's lower limit

// One Gaussian term of the shear kernel: weight * exp(-lambda |m - a|^2), with its grid axes.
struct ShearTerm {
  double weight, lambda;
  const GaussianAxis *gx, *gy;
  bool with_weights = false;  // also sum w_i exp(...) alone into out.w (the stick saturation's denominator)
  double aniso = 0;           // + aniso lambda d (d . v): the along-the-load anisotropy (contact's far field)
};

// One shear sum over one field: what it reads (the model, the field's points), the buffers it writes and the
// contact-following shift of every anchor, which it computes first.
class ShearPass {
 public:
  ShearPass(const HydroShearModel& model, const FieldPoints& field, ShearBuffers& buffers)
      : m(model), f(field), sc(buffers) {}
  void run();

 private:
  void contact_shift();
  bool factored(const ShearTerm& term) const;  // the term's Gaussians factor on the marker grid
  // Every term over the shared point operands, the products in T.
  template <typename T>
  void sum_terms(std::span<const ShearTerm> terms) const;
  template <typename T>
  void add_term(const ShearTerm& term, int mp) const;
  void add_sums(const ShearTerm& term, const double* tot, double kl) const;
  static Vec2 aniso_term(const ShearTerm& term, const Vec2& d, double vx, double vy);
  // vx, vy, vw: the point's term already scaled by the term's weight.
  void shear_point_slow(const ShearTerm& term, int i, double vx, double vy, double vw) const;

  const HydroShearModel& m;
  const FieldPoints& f;
  ShearBuffers& sc;
  double shift_x = 0, shift_y = 0;
};

}  // namespace

// M_s(m_j) = sum_i w_i (-f_i^xy) exp(-lambda_s |m_j - a_i|^2), anchor a_i = o_i + u_i at the real (not
// shifted) point, as the authors' code; the 3-D distance (code). Unscaled (kappa_s applied on output). The
// variants are data: the layer's near field and the contact's far field are more Gaussian terms (ShearTerm), the
// stick zone sums the weights alone beside the field, the contact shifts every anchor (follow).
//
// One pass for every term over operands shared by the terms: v = -w f^xy, w and the anchor a, formed once
// (kernels::point_operands). On a uniform marker grid each term's Gaussian splits by axis into factors of at most
// 1 (kernels::axis_exponents), 3 exps per point batched through exp_in_place, whose ratio recurrences
//   exp(-l |m_rc - a_i|^2) = (gx0_i X_i[c]) (gy0_i Y_i[r])   (GaussianAxis)
// run in double and are stored as T; the sum over points is then a small matrix product per chunk of points
// small enough to stay in the first-level cache, into lane partial sums (kernels::add_products_acc).
// T = float only where the parameter float32 asks for it (the contact variant's default): the sums change by
// ~1e-6 of themselves against double (tests/test_hydroshear_contact.cpp), for half the memory traffic and twice
// the vector width, the precision the authors' GPU code computes in. Fits run it in double (their cost must be
// smooth far below that: core/calibration/fit_engine.cpp).
void ShearPass::run() {
  const int nm = m.markers();
  sc.out.x.assign(nm, 0.0);
  sc.out.y.assign(nm, 0.0);
  if (f.size() == 0) return;
  const bool stick = m.k.stick_sat > 0;
  if (stick) sc.out.w.assign(nm, 0.0);
  contact_shift();
  const ShearTerm terms[] = {{1.0, m.k.lambda_s, &m.gauss_x, &m.gauss_y, stick},
                             {m.k.beta_s, m.k.lambda_s2, &m.gauss_x2, &m.gauss_y2},
                             {m.k.beta_s3, m.k.lambda_s3, &m.gauss_x3, &m.gauss_y3, false, m.k.aniso_s3}};
  if (m.k.single_precision)
    sum_terms<float>(terms);
  else
    sum_terms<double>(terms);
  if (!stick) return;
  // The stick zone: where the contact's weights pile up, the field tends to their weighted mean state
  // instead of growing with their sum (docs/effects.md, "The stick zone").
  for (int j = 0; j < nm; ++j) {
    const double scale = 1.0 / (1.0 + m.k.stick_sat * sc.out.w[j]);
    sc.out.x[j] *= scale;
    sc.out.y[j] *= scale;
  }
}

// The contact-following shift of every anchor: -follow times the weighted mean tangential state (the
// state points back to where a point stuck, so the shift points along the contact's motion).
void ShearPass::contact_shift() {
  shift_x = shift_y = 0;
  if (m.k.follow == 0) return;
  const PointColumns& F = *f.state;
  const int n = F.size();
  double sw = 0, sx = 0, sy = 0;
  for (int i = 0; i < n; ++i) {
    const double u_n = f.un[i];
    const double w = m.k.weight_paper ? -f.phi[i] : m.k.E * u_n;
    // The tangential part: with the paper's normal the state's normal component is u_n along n.
    const double tx = F.ux[i] - (m.k.normal_indenter ? u_n * f.nx[i] : 0.0);
    const double ty = F.uy[i] - (m.k.normal_indenter ? u_n * f.ny[i] : 0.0);
    sw += w, sx += w * tx, sy += w * ty;
  }
  if (sw <= 0) return;
  shift_x = -m.k.follow * sx / sw;
  shift_y = -m.k.follow * sy / sw;
}

namespace {
// Exponent budget of the factored form: every partial product stays above e^-kMaxTotalExponent, far
// from underflow (e^-708); a point beyond it uses one exp per axis coordinate instead.
constexpr double kMaxTotalExponent = 650;

// Whether an axis' ratio recurrence stays in double's range: its factor q^k = exp(-2 l h^2 k) must not
// underflow before the last marker (a Gaussian far narrower than the pitch: lambda near 1e8 at 2 mm).
bool recurrence_in_range(const GaussianAxis& g) {
  return g.uniform() && 2 * g.lambda() * g.pitch() * g.pitch() * std::max(g.size() - 2, 0) <= kMaxTotalExponent;
}

kernels::AxisConstants axis_constants(const GaussianAxis& gx, const GaussianAxis& gy, double lambda, double z0) {
  return {lambda, z0, gx.front(), gx.back(), gx.pitch(), gy.front(), gy.back(), gy.pitch(), kMaxTotalExponent};
}
}  // namespace

bool ShearPass::factored(const ShearTerm& term) const {
  return m.grid.is_grid && recurrence_in_range(*term.gx) && recurrence_in_range(*term.gy);
}

// The operands every term shares, then each term in turn (see run).
template <typename T>
void ShearPass::sum_terms(std::span<const ShearTerm> terms) const {
  const PointColumns& F = *f.state;
  const int n = F.size();
  const int mp = (n + 7) / 8 * 8;  // whole 8-float vectors
  // point_operands writes the n points; the padding up to mp is zero (zero weight, anchors at the origin).
  for (auto* v : {&sc.wvx, &sc.wvy, &sc.ww, &sc.anchor_x, &sc.anchor_y, &sc.anchor_z}) {
    v->resize(mp);
    std::fill(v->begin() + n, v->end(), 0.0);
  }
  const kernels::ShearColumns cols{f.x, f.y, f.z, F.ux.data(), F.uy.data(), F.uz.data(), f.un, f.phi, f.nx, f.ny, f.nz};
  const kernels::PointConstants k{m.k.E, m.k.K, m.k.weight_paper, !m.k.normal_indenter, shift_x, shift_y};
  kernels::point_operands(
      cols, k, n,
      {sc.wvx.data(), sc.wvy.data(), sc.ww.data(), sc.anchor_x.data(), sc.anchor_y.data(), sc.anchor_z.data()});
  if constexpr (std::is_same_v<T, float>) {  // in double, the terms read sc.wvx, wvy, ww themselves
    auto& ops = sc.operands<T>();
    for (auto [from, to] : {std::pair{&sc.wvx, &ops.vx}, std::pair{&sc.wvy, &ops.vy}, std::pair{&sc.ww, &ops.w}}) {
      to->resize(mp);
      std::copy(from->begin(), from->end(), to->begin());  // rounded to float
    }
  }
  for (const ShearTerm& term : terms)
    if (term.weight > 0) add_term<T>(term, mp);
}

namespace {
// The point operands in the products' precision: float copies, or the double columns themselves.
template <typename T>
kernels::TermWeights<T> term_weights(ShearBuffers& sc, bool with_weights) {
  if constexpr (std::is_same_v<T, float>) {
    auto& ops = sc.operands<T>();
    return {ops.vx.data(), ops.vy.data(), with_weights ? ops.w.data() : nullptr, sc.fast.data()};
  } else {
    return {sc.wvx.data(), sc.wvy.data(), with_weights ? sc.ww.data() : nullptr, sc.fast.data()};
  }
}
}  // namespace

// One Gaussian term: its slow points one by one, the rest factored per chunk.
template <typename T>
void ShearPass::add_term(const ShearTerm& term, int mp) const {
  constexpr int kChunk = 96;  // points per chunk: the operands (at most 55 rows of floats) stay in L1
  const int n = f.size();
  const double* vx = sc.wvx.data();
  const double* vy = sc.wvy.data();
  const double* w = sc.ww.data();
  const double tw = term.weight;
  if (!factored(term)) {
    for (int i = 0; i < n; ++i)
      if (vx[i] != 0 || vy[i] != 0 || (term.with_weights && w[i] != 0))
        shear_point_slow(term, i, tw * vx[i], tw * vy[i], tw * w[i]);
    return;
  }
  sc.axis_args.resize(4 * static_cast<std::size_t>(mp));
  sc.fast.resize(mp);
  double* e0 = sc.axis_args.data();
  const kernels::AxisExponents exponents{e0, e0 + mp, e0 + std::ptrdiff_t{2} * mp, e0 + std::ptrdiff_t{3} * mp};
  const int slow = kernels::axis_exponents(sc.anchor_x.data(), sc.anchor_y.data(), sc.anchor_z.data(),
                                           axis_constants(*term.gx, *term.gy, term.lambda, m.grid.z0), mp, exponents,
                                           sc.fast.data());
  const std::uint8_t* fast = sc.fast.data();
  for (int i = 0; i < n && slow > 0; ++i)
    if (!fast[i] && (vx[i] != 0 || vy[i] != 0 || (term.with_weights && w[i] != 0)))
      shear_point_slow(term, i, tw * vx[i], tw * vy[i], tw * w[i]);
  exp_in_place(e0, 4 * mp);
  const kernels::AxisFactors factors{exponents.x0, exponents.rx, exponents.y0, exponents.ry};
  const int rows = m.grid.rows, cols = m.grid.cols, nm = rows * cols;
  const kernels::GridAxes grid{rows, cols, term.gx->q(), term.gy->q(), m.grid.xs.data(), m.grid.ys.data()};
  const int cols_pad = (cols + 2) / 3 * 3;
  const bool aniso = term.aniso != 0;
  // Blocks of W per marker row and of X per column: isotropic [vx; vy; (w)] against X; anisotropic
  // [W1; WB (2); WC] against [XC; XA; XB] (kernels::aniso_operands).
  const int w_blocks = aniso ? 4 : (term.with_weights ? 3 : 2);
  const int x_blocks = aniso ? 3 : 1;
  auto& ops = sc.operands<T>();
  constexpr int kLanes = 32 / sizeof(T);  // the partial sums' lanes per output (add_products_acc)
  ops.X.resize(static_cast<std::size_t>(x_blocks) * cols_pad * kChunk);
  ops.W.resize(static_cast<std::size_t>(w_blocks) * rows * kChunk);
  sc.run.resize(kChunk);
  ops.S.assign(kLanes * static_cast<std::size_t>(w_blocks) * nm, T(0));
  T* S = ops.S.data();
  const double kl = term.aniso * term.lambda;
  const kernels::TermWeights<T> weights = term_weights<T>(sc, term.with_weights);
  for (int off = 0; off < mp; off += kChunk) {
    const int len = std::min(kChunk, mp - off);  // a multiple of 8, as mp and kChunk are
    T* X = ops.X.data();
    T* W = ops.W.data();
    const std::ptrdiff_t xrows = static_cast<std::ptrdiff_t>(cols_pad) * len;
    const std::ptrdiff_t wrows = static_cast<std::ptrdiff_t>(rows) * len;
    if (aniso) {
      kernels::aniso_operands(factors.at(off), weights.at(off), sc.anchor_x.data() + off, sc.anchor_y.data() + off, kl,
                              grid, len, X, W, sc.run.data());
      kernels::add_products_acc(W, rows, X + xrows, cols, len, S);                                // W1 XA
      kernels::add_products_acc(W + wrows, 2 * rows, X + 2 * xrows, cols, len, S + kLanes * nm);  // WB XB
      kernels::add_products_acc(W + 3 * wrows, rows, X, cols, len, S + kLanes * 3 * nm);          // WC XC
    } else {
      kernels::term_operands(factors.at(off), weights.at(off), grid, len, X, W, sc.run.data());
      kernels::add_products_acc(W, w_blocks * rows, X, cols, len, S);
    }
  }
  sc.sums.resize(static_cast<std::size_t>(w_blocks) * nm);
  kernels::lane_sums(S, w_blocks * nm, sc.sums.data());
  add_sums(term, sc.sums.data(), aniso ? kl : 0.0);
}

// The lanes' totals into the field: S_x = W1 XA + kl WB[0] XB, S_y = WC XC + kl WB[1] XB for an anisotropic
// term (kernels::aniso_operands), S_x, S_y (and the weights') blocks as they are for an isotropic one.
void ShearPass::add_sums(const ShearTerm& term, const double* tot, double kl) const {
  const int nm = m.markers();
  const double tw = term.weight;
  double* sx = sc.out.x.data();
  double* sy = sc.out.y.data();
  if (term.aniso != 0) {
    for (int j = 0; j < nm; ++j) {
      sx[j] += tw * (tot[j] + kl * tot[nm + j]);
      sy[j] += tw * (tot[3 * nm + j] + kl * tot[2 * nm + j]);
    }
    return;
  }
  for (int j = 0; j < nm; ++j) {
    sx[j] += tw * tot[j];
    sy[j] += tw * tot[nm + j];
  }
  if (term.with_weights)
    for (int j = 0; j < nm; ++j) sc.out.w[j] += tw * tot[2 * nm + j];
}

// A point's term v at in-plane offset d (anchor to marker), with the term's anisotropy: v + k l d (d . v).
Vec2 ShearPass::aniso_term(const ShearTerm& term, const Vec2& d, double vx, double vy) {
  const Vec2 v(vx, vy);
  return term.aniso == 0 ? v : Vec2(v + term.aniso * term.lambda * d * d.dot(v));
}

// One field point's share of the shear sum with one exp per axis coordinate (or per marker off a
// grid): for anchors too far for the factored form, and for marker layouts that are not a uniform grid.
void ShearPass::shear_point_slow(const ShearTerm& term, int i, double vx, double vy, double vw) const {
  const PointColumns& F = *f.state;
  const Vec3 a(f.x[i] + F.ux[i] + shift_x, f.y[i] + F.uy[i] + shift_y, f.z[i] + F.uz[i]);
  const double ls = term.lambda;
  double* sx = sc.out.x.data();
  double* sy = sc.out.y.data();
  double* sw = term.with_weights ? sc.out.w.data() : nullptr;
  if (m.grid.is_grid) {
    const int rows = m.grid.rows, cols = m.grid.cols;
    sc.ex.resize(cols);
    sc.ey.resize(rows);
    term.gx->eval(a.x(), sc.ex.data());
    term.gy->eval(a.y(), sc.ey.data());
    const double ez = std::exp(-ls * (m.grid.z0 - a.z()) * (m.grid.z0 - a.z()));
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c) {
        const double g = ez * sc.ey[r] * sc.ex[c];
        const Vec2 v = aniso_term(term, Vec2(m.grid.xs[c] - a.x(), m.grid.ys[r] - a.y()), vx, vy);
        sx[r * cols + c] += v.x() * g;
        sy[r * cols + c] += v.y() * g;
        if (sw != nullptr) sw[r * cols + c] += vw * g;
      }
    return;
  }
  // Exponents first, then one vectorised exp over them (a point's 327 TacTip pins: this was a third of a scored
  // frame's time in libm's scalar exp). Below kMinExponent the Gaussian is < 1e-304 of its peak: nothing.
  const int nm = m.markers();
  sc.marker_gauss.resize(nm);
  double* g = sc.marker_gauss.data();
  const double p_a[3] = {a.x(), a.y(), a.z()}, v[3] = {vx, vy, vw};
  kernels::scattered_exponents(m.marker_x.data(), m.marker_y.data(), m.marker_z.data(), nm, p_a, ls, kMinExponent, g);
  exp_in_place(g, nm);
  kernels::scattered_add(m.marker_x.data(), m.marker_y.data(), nm, p_a, v, term.aniso * ls, g, {sx, sy, sw});
}

const ShearSums& shear_sum(const HydroShearModel& m, const FieldPoints& f, ShearBuffers& buf) {
  ShearPass(m, f, buf).run();
  return buf.out;
}

}  // namespace sb::hydroshear
