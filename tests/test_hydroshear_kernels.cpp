// HydroShear's column kernels (core/models/hydroshear_kernels) on cases worked out by hand. The whole batch is
// checked against a dense reference loop in test_model_kernels.cpp; these pin each kernel alone.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <vector>

#include "core/models/hydroshear_kernels.hpp"
#include "core/models/model_common.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_hydroshear_kernels {

using namespace sb;
namespace kernels = sb::hydroshear_kernels;

namespace {

// Metres: the states are 1e-5..1e-4 m, computed with a few roundings.
constexpr double kStateTol = 1e-18;
// Relative: sums of a few exps and products.
constexpr double kRelTol = 1e-12;

struct StepCase {
  double s_prev, q[3], s, p[3], o[3];
};

struct StepResult {
  std::vector<double> ux, uy, uz, un;
  std::vector<std::uint8_t> slip;
};

// Runs advance_points on the cases (split along +z, cone mu E / K = 0.5), both through the +z
// instantiation and through explicit normal columns (0, 0, 1): the two must agree exactly.
StepResult advance(const std::vector<StepCase>& cases, bool normal_z) {
  const int n = static_cast<int>(cases.size());
  std::vector<double> sp(n), qx(n), qy(n), qz(n), s(n), px(n), py(n), pz(n), ox(n), oy(n), oz(n), nx(n, 0.0),
      ny(n, 0.0), nz(n, 1.0);
  for (int i = 0; i < n; ++i) {
    const StepCase& c = cases[i];
    sp[i] = c.s_prev, qx[i] = c.q[0], qy[i] = c.q[1], qz[i] = c.q[2];
    s[i] = c.s, px[i] = c.p[0], py[i] = c.p[1], pz[i] = c.p[2];
    ox[i] = c.o[0], oy[i] = c.o[1], oz[i] = c.o[2];
  }
  const kernels::AdvanceColumns in{sp.data(), qx.data(), qy.data(), qz.data(), s.data(),  px.data(), py.data(),
                                   pz.data(), ox.data(), oy.data(), oz.data(), nx.data(), ny.data(), nz.data()};
  StepResult r{std::vector<double>(n), std::vector<double>(n), std::vector<double>(n), std::vector<double>(n),
               std::vector<std::uint8_t>(n)};
  kernels::advance_points(in, normal_z, 0.5, n, r.ux.data(), r.uy.data(), r.uz.data(), r.un.data(), r.slip.data());
  return r;
}

}  // namespace

TEST_CASE("advance_points: stick, slip, entry fraction and release of the normal part", "[hydroshear][kernels]") {
  const std::vector<StepCase> cases = {
      // 0. Tracked (s_prev = s: alpha = 1 by the 0/0 rule), moved +x by 0.02 mm with u = (0, 0, 0.1 mm):
      //    trial (-0.02, 0, 0.1) mm; |u_t| = 0.02 <= cap 0.5 * 0.1 = 0.05 mm: stick, u = trial.
      {-1e-4, {0, 0, -1e-4}, -1e-4, {2e-5, 0, -1e-4}, {0, 0, 1e-4}},
      // 1. The same moved 0.08 mm: |u_t| = 0.08 > 0.05: slip, u_t clipped to -0.05 mm.
      {-1e-4, {0, 0, -1e-4}, -1e-4, {8e-5, 0, -1e-4}, {0, 0, 1e-4}},
      // 2. Entering: s_prev = +0.02 mm, s = -0.06 mm after moving 0.08 mm down: alpha = (0.06 - 0) /
      //    (0.02 + 0.06) = 0.75, so u = 0.75 * 0.08 = 0.06 mm along +z, stick.
      {2e-5, {0, 0, 2e-5}, -6e-5, {0, 0, -6e-5}, {0, 0, 0}},
      // 3. Moved up 0.03 mm with u = (0.01, 0, 0.01) mm: trial normal 0.01 - 0.03 < 0, u_n = 0, the cone
      //    closes and u_t = 0.01 mm is clipped to 0: u = 0, slip.
      {-1e-4, {0, 0, -1e-4}, -1e-4, {0, 0, -7e-5}, {1e-5, 0, 1e-5}},
      // 4. A fifth point (not a whole vector of four) diagonal stick: moved (+0.01, -0.01) mm, u_n 0.1 mm:
      //    u_t = (-0.01, 0.01) mm, |u_t| = 0.0141 <= 0.05.
      {-1e-4, {0, 0, -1e-4}, -1e-4, {1e-5, -1e-5, -1e-4}, {0, 0, 1e-4}},
  };
  for (bool normal_z : {true, false}) {
    const StepResult r = advance(cases, normal_z);
    CHECK(r.ux[0] == Approx(-2e-5).margin(kStateTol));
    CHECK(r.uz[0] == Approx(1e-4).margin(kStateTol));
    CHECK(r.un[0] == Approx(1e-4).margin(kStateTol));
    CHECK(r.slip[0] == 0);
    CHECK(r.ux[1] == Approx(-5e-5).margin(kStateTol));
    CHECK(r.slip[1] == 1);
    CHECK(r.uz[2] == Approx(6e-5).margin(kStateTol));
    CHECK(r.ux[2] == 0.0);
    CHECK(r.slip[2] == 0);
    CHECK(r.un[3] == 0.0);
    CHECK(r.ux[3] == 0.0);
    CHECK(r.uz[3] == 0.0);
    CHECK(r.slip[3] == 1);
    CHECK(r.ux[4] == Approx(-1e-5).margin(kStateTol));
    CHECK(r.uy[4] == Approx(1e-5).margin(kStateTol));
    CHECK(r.slip[4] == 0);
  }
}

TEST_CASE("flat_pad_phi equals the box distance of FlatPad", "[hydroshear][kernels]") {
  // Pad 20 x 16 mm, 4 mm thick: z in [-4, 0] mm.
  const FlatPad pad{10e-3, 8e-3, 4e-3};
  // Inside 1 mm deep: -1 mm. Above the centre by 3 mm: +3 mm. Outside a corner by (2, 3, 1) mm:
  // sqrt(4 + 9 + 1) mm.
  const std::vector<double> x = {0, 0, 12e-3, 5e-3, -9e-3}, y = {0, 0, 11e-3, -7.5e-3, 1e-3},
                            z = {-1e-3, 3e-3, 1e-3, -0.2e-3, -3.9e-3};
  std::vector<double> phi(x.size());
  const std::array<double, 3> no_shift = {0, 0, 0};
  kernels::flat_pad_phi(pad, no_shift.data(), x.data(), y.data(), z.data(), static_cast<int>(x.size()), phi.data());
  CHECK(phi[0] == Approx(-1e-3).epsilon(kRelTol));
  CHECK(phi[1] == Approx(3e-3).epsilon(kRelTol));
  CHECK(phi[2] == Approx(std::sqrt(14.0) * 1e-3).epsilon(kRelTol));
  for (std::size_t i = 0; i < x.size(); ++i)
    CHECK(phi[i] == Approx(pad.value(Vec3(x[i], y[i], z[i]))).epsilon(kRelTol));
  // The shift moves the query point: (0, 0, -1 mm) shifted up 3 mm is 2 mm above the pad.
  const std::array<double, 3> up = {0, 0, 3e-3};
  kernels::flat_pad_phi(pad, up.data(), x.data(), y.data(), z.data(), 1, phi.data());
  CHECK(phi[0] == Approx(2e-3).epsilon(kRelTol));
}

TEST_CASE("shear kernels: one anchor on a marker gives the Gaussian of the grid", "[hydroshear][kernels]") {
  // Grid 4 columns x 3 rows at 1 mm pitch, z0 = 0; lambda_s = 1e6 m^-2, so a marker at (c, r) mm from
  // the anchor weighs exp(-(c^2 + r^2)).
  constexpr double l = 1e6, h = 1e-3;
  constexpr int cols = 4, rows = 3;
  // One point with state u = (0.1, 0, 0.2) mm and anchor a = o + u at marker (0, 0): o = -u. With
  // E = K = 1 and the code's weight w = E u_n = 0.2 mm, f_x = K u_x = 0.1 mm:
  // vx = -w f_x = -2e-8 m^2, vy = 0, and S_x[r][c] = -2e-8 exp(-(c^2 + r^2)).
  // A second point with its anchor 1 m away exceeds the exponent budget: fast = 0, so its weight (w = 1e-4,
  // vx = -1e-8) must not reach the sums.
  const std::vector<double> px = {-1e-4, 1.0}, py = {0, 0}, pz = {-2e-4, 0}, ux = {1e-4, 0}, uy = {0, 0},
                            uz = {2e-4, 0}, un = {2e-4, 1e-4}, phi = {-1e-4, -1e-4};
  const kernels::ShearColumns in{px.data(), py.data(),  pz.data(), ux.data(), uy.data(), uz.data(),
                                 un.data(), phi.data(), nullptr,   nullptr,   nullptr};
  constexpr int mp = 8;  // two points padded to one vector of floats: zero weight, anchors at the origin
  std::vector<double> vx(mp, 0.0), vy(mp, 0.0), w(mp, 0.0), ax(mp, 0.0), ay(mp, 0.0), az(mp, 0.0);
  kernels::point_operands(in, {1, 1, false, true}, 2,
                          {vx.data(), vy.data(), w.data(), ax.data(), ay.data(), az.data()});
  CHECK(vx[0] == Approx(-2e-8).epsilon(kRelTol));
  CHECK(vy[0] == 0.0);
  CHECK(w[0] == Approx(2e-4).epsilon(kRelTol));
  CHECK(ax[0] == Approx(0).margin(1e-18));
  CHECK(az[0] == Approx(0).margin(1e-18));
  const kernels::AxisConstants k{l, 0, 0, (cols - 1) * h, h, 0, (rows - 1) * h, h, 650};
  std::vector<double> args(4 * mp);
  std::vector<std::uint8_t> fast(mp);
  const kernels::AxisExponents e{args.data(), args.data() + mp, args.data() + 2 * mp, args.data() + 3 * mp};
  CHECK(kernels::axis_exponents(ax.data(), ay.data(), az.data(), k, mp, e, fast.data()) == 1);
  CHECK(fast[0] == 1);
  CHECK(fast[1] == 0);
  exp_in_place(args.data(), 4 * mp);
  const double q = std::exp(-2 * l * h * h);
  constexpr int cols_pad = 6;  // 4 -> 6 columns, 3 blocks of W rows (vx, vy, w)
  std::vector<double> X(cols_pad * mp), W(3 * rows * mp), run(mp);
  const kernels::GridAxes grid{rows, cols, q, q, nullptr, nullptr};
  kernels::term_operands({e.x0, e.rx, e.y0, e.ry}, {vx.data(), vy.data(), w.data(), fast.data()}, grid, mp, X.data(),
                         W.data(), run.data());
  const int nm = rows * cols;
  std::vector<double> Sacc(4 * 3 * nm, 0.0), S(3 * nm);  // 4 lanes per output
  kernels::add_products_acc(W.data(), 3 * rows, X.data(), cols, mp, Sacc.data());
  kernels::lane_sums(Sacc.data(), 3 * nm, S.data());
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const double g = std::exp(-(c * c + r * r));
      CHECK(S[r * cols + c] == Approx(-2e-8 * g).epsilon(kRelTol));
      CHECK(S[nm + r * cols + c] == 0.0);
      CHECK(S[2 * nm + r * cols + c] == Approx(2e-4 * g).epsilon(kRelTol));
    }
}

TEST_CASE("shear kernels: the anisotropic operands in single precision give G (v + k l d (d . v))",
          "[hydroshear][kernels]") {
  // The grid and point of the test above (lambda = 1e6 m^-2, 1 mm pitch, the anchor on marker (0, 0),
  // vx = -2e-8 m^2, vy = 0), anisotropy k = 2, so kl = 2e6 and at marker (c, r) d = (c, r) mm, l |d|^2 =
  // c^2 + r^2, kl d (d . v) = 2 vx (c^2, c r):
  //   S_x = vx e^-(c^2 + r^2) (1 + 2 c^2),  S_y = vx e^-(c^2 + r^2) 2 c r.
  // Assembled as the shear pass's add_sums does: S_x = W1 XA + kl WB[0] XB, S_y = WC XC + kl WB[1] XB.
  constexpr double kFloatRel = 1e-6;  // single-precision operands, sums in double
  constexpr double l = 1e6, h = 1e-3, kAniso = 2, vx0 = -2e-8;
  constexpr int cols = 4, rows = 3, mp = 8, cols_pad = 6;
  std::vector<float> vx(mp, 0.0f), vy(mp, 0.0f);
  std::vector<double> args(4 * mp, 0.0), ax(mp, 0.0), ay(mp, 0.0);
  std::vector<std::uint8_t> fast(mp, 0);
  vx[0] = static_cast<float>(vx0), fast[0] = 1;
  // Exponents of the anchor at the grid's first marker: ex0 = ey0 = 0, rx = -l (h^2 + 2 h dx0) = -1, ry = -1.
  args[mp] = -1, args[3 * mp] = -1;
  exp_in_place(args.data(), 4 * mp);
  const double q = std::exp(-2 * l * h * h);
  std::vector<double> xs(cols), ys(rows);
  for (int c = 0; c < cols; ++c) xs[c] = c * h;
  for (int r = 0; r < rows; ++r) ys[r] = r * h;
  std::vector<float> X3(3 * cols_pad * mp), W4(4 * rows * mp);
  std::vector<double> run(mp);
  const double kl = kAniso * l;
  kernels::aniso_operands({args.data(), args.data() + mp, args.data() + 2 * mp, args.data() + 3 * mp},
                          {vx.data(), vy.data(), nullptr, fast.data()}, ax.data(), ay.data(), kl,
                          {rows, cols, q, q, xs.data(), ys.data()}, mp, X3.data(), W4.data(), run.data());
  const float* XC = X3.data();
  const float* XA = XC + cols_pad * mp;
  const float* XB = XA + cols_pad * mp;
  const float* W1 = W4.data();
  const float* WB = W1 + rows * mp;
  const float* WC = WB + 2 * rows * mp;
  const int nm = rows * cols;
  std::vector<float> Sacc(8 * 4 * nm, 0.0f);  // 8 lanes per output
  kernels::add_products_acc(W1, rows, XA, cols, mp, Sacc.data());
  kernels::add_products_acc(WB, 2 * rows, XB, cols, mp, Sacc.data() + 8 * nm);
  kernels::add_products_acc(WC, rows, XC, cols, mp, Sacc.data() + 8 * 3 * nm);
  std::vector<double> S(4 * nm, 0.0);
  for (int j = 0; j < 4 * nm; ++j)
    for (int k = 0; k < 8; ++k) S[j] += Sacc[8 * j + k];
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const int j = r * cols + c;
      const double g = vx0 * std::exp(-(c * c + r * r));
      INFO("marker (" << c << ", " << r << ")");
      CHECK(S[j] + kl * S[nm + j] == Approx(g * (1 + kAniso * c * c)).epsilon(kFloatRel));
      CHECK(S[3 * nm + j] + kl * S[2 * nm + j] == Approx(g * kAniso * c * r).epsilon(kFloatRel).margin(1e-30));
    }
}

TEST_CASE("shear kernels: single precision holds an anchor far from the grid's first marker", "[hydroshear][kernels]") {
  // 9 columns x 7 rows at 1 mm pitch (the GelSight Mini's grid shape), lambda = 4e6 m^-2, one point with
  // its anchor on the last marker (8, 6) mm: at marker (c, r) the Gaussian is
  //   exp(-4 ((8 - c)^2 + (6 - r)^2)),
  // 1 on that marker and e^-4 on its neighbours. The anchor is l (x0 - a)^2 = 256 from the first column:
  // a factor referred to the grid's first marker alone would pass float's range (e^88), one split by axis
  // stays at most 1 on every marker. With weights vx = -3e-8, vy = 5e-8, w = 2e-4 the sums are those
  // weights times the Gaussian. A second point with its anchor 1 m away is past the exponent budget: not fast.
  constexpr double kFloatRel = 1e-6;  // single-precision operands, sums in double
  // Where the float products underflow (far from the anchor) the sums are 0: below this they agree.
  constexpr double kUnderflow = 1e-40;
  constexpr double l = 4e6, h = 1e-3;
  constexpr int cols = 9, rows = 7, mp = 8;
  const std::vector<double> ax = {8 * h, 1.0, 0, 0, 0, 0, 0, 0}, ay = {6 * h, 0, 0, 0, 0, 0, 0, 0}, az(mp, 0.0);
  const kernels::AxisConstants k{l, 0, 0, (cols - 1) * h, h, 0, (rows - 1) * h, h, 650};
  std::vector<double> args(4 * mp);
  std::vector<std::uint8_t> fast(mp);
  const kernels::AxisExponents e{args.data(), args.data() + mp, args.data() + 2 * mp, args.data() + 3 * mp};
  const int slow = kernels::axis_exponents(ax.data(), ay.data(), az.data(), k, mp, e, fast.data());
  CHECK(fast[0] == 1);
  CHECK(fast[1] == 0);
  CHECK(slow == 1);
  CHECK(args[0] == Approx(-256).epsilon(1e-12));       // ex0 = -l (0 - 8 mm)^2
  CHECK(args[2 * mp] == Approx(-144).epsilon(1e-12));  // ey0 = -l (0 - 6 mm)^2
  exp_in_place(args.data(), 4 * mp);
  std::vector<float> vx(mp, 0.0f), vy(mp, 0.0f), w(mp, 0.0f);
  vx[0] = -3e-8f, vy[0] = 5e-8f, w[0] = 2e-4f;
  vx[1] = 1.0f;  // not fast: its weight must not reach the sums
  const double q = std::exp(-2 * l * h * h);
  constexpr int cols_pad = 9;
  std::vector<float> X(cols_pad * mp), W(3 * rows * mp);
  std::vector<double> run(mp);
  kernels::term_operands({e.x0, e.rx, e.y0, e.ry}, {vx.data(), vy.data(), w.data(), fast.data()},
                         {rows, cols, q, q, nullptr, nullptr}, mp, X.data(), W.data(), run.data());
  const int nm = rows * cols;
  std::vector<float> Sacc(8 * 3 * nm, 0.0f);
  kernels::add_products_acc(W.data(), 3 * rows, X.data(), cols, mp, Sacc.data());
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const int j = r * cols + c;
      const double g = std::exp(-4.0 * ((8 - c) * (8 - c) + (6 - r) * (6 - r)));
      double s[3] = {0, 0, 0};
      for (int b = 0; b < 3; ++b)
        for (int lane = 0; lane < 8; ++lane) s[b] += Sacc[8 * (b * nm + j) + lane];
      INFO("marker (" << c << ", " << r << ")");
      CHECK(s[0] == Approx(-3e-8 * g).epsilon(kFloatRel).margin(kUnderflow));
      CHECK(s[1] == Approx(5e-8 * g).epsilon(kFloatRel).margin(kUnderflow));
      CHECK(s[2] == Approx(2e-4 * g).epsilon(kFloatRel).margin(kUnderflow));
    }
}

TEST_CASE("dilation_sum adds the depth-weighted kernel rows of the inside markers", "[hydroshear][kernels]") {
  // Three markers (stride 8): rows K[k][j] = 10 k + j for x and -(10 k + j) for y. Markers 0 and 2 inside
  // at depths 1 and 2: d_x[j] = (0 + j) + 2 (20 + j) = 40 + 3 j, d_y = -d_x.
  constexpr int markers = 3;
  const int stride = kernels::dilation_stride(markers);
  REQUIRE(stride == 8);
  std::vector<double> Kx(markers * stride, 0.0), Ky(markers * stride, 0.0);
  for (int kk = 0; kk < markers; ++kk)
    for (int j = 0; j < markers; ++j) {
      Kx[kk * stride + j] = 10.0 * kk + j;
      Ky[kk * stride + j] = -(10.0 * kk + j);
    }
  const std::vector<int> ks = {0, 2};
  const std::vector<double> h = {1, 2};
  std::vector<double> dx(stride), dy(stride);
  kernels::dilation_sum(Kx.data(), Ky.data(), stride, ks.data(), h.data(), 2, dx.data(), dy.data());
  for (int j = 0; j < markers; ++j) {
    CHECK(dx[j] == 40.0 + 3 * j);
    CHECK(dy[j] == -(40.0 + 3 * j));
  }
  for (int j = markers; j < stride; ++j) CHECK(dx[j] == 0.0);  // the zero padding stays zero
}

}  // namespace test_hydroshear_kernels
