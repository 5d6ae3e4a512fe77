// The optimised batched kernels (cluster cull, Gaussian recurrences, k-major dilation, hoisted
// rotations) against straightforward reference loops written here from the model equations
// (docs/models.md): every point, every marker, one std::exp per (point, marker). Run on a few envs of the
// benchmark workload (BENCH_WORKLOAD.md), every one of its 50 steps (press, hold, slide and twist).
#include <catch2/catch.hpp>

#include "mini_grid.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/api/bench_run.hpp"
#include "core/models/bench_workload.hpp"
#include "core/models/fots.hpp"
#include "core/models/hydroshear.hpp"
#include "core/models/tacsl.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_model_kernels {

using sbtest::kMiniMarkers;

using namespace sb;

namespace {

// Relative agreement asked of the optimised kernels: |d_opt - d_ref| <= kRelTol * max_j |d_ref_j| per
// slot and step (sums in another order and the recurrences round differently, ~1e-15).
constexpr double kRelTol = 1e-9;
// px: the agreement asked of a field that is exactly zero in the reference (no contact).
constexpr double kZeroFieldPx = 1e-15;
constexpr int kTestEnvs = 6;  // 12 slots: more than one parallel task would need, run through the batch

struct Workload {
  std::shared_ptr<const Sensor> sensor;
  std::shared_ptr<const Indenter> peg;
  std::vector<std::vector<Pose>> X;  // [step][slot]
  int slots;
};

const Workload& workload() {
  static const Workload w = [] {
    Workload w;
    w.sensor = std::make_shared<Sensor>(make_default_sensor());
    auto peg = std::make_shared<Indenter>();
    peg->sdf = make_capped_cylinder_sdf(kPegRadius, kPegLength);
    peg->samples = bench_peg_points();
    w.peg = peg;
    BenchWorkloadSpec spec;
    spec.envs = kTestEnvs;
    spec.steps = kBenchMaxSteps;
    w.X = bench_trajectory(spec);
    w.slots = kTestEnvs * kBenchSensors;
    return w;
  }();
  return w;
}

// Compares one step of all slots; returns the largest reference field seen (to show contact happened).
double compare(const std::vector<Vec2>& opt, const std::vector<std::vector<Vec2>>& ref, int step) {
  double seen = 0;
  for (std::size_t slot = 0; slot < ref.size(); ++slot) {
    double scale = 0, err = 0;
    for (std::size_t j = 0; j < ref[slot].size(); ++j) {
      scale = std::max(scale, ref[slot][j].norm());
      err = std::max(err, (opt[slot * ref[slot].size() + j] - ref[slot][j]).norm());
    }
    INFO("step " << step << " slot " << slot << " max |ref| " << scale << " px");
    CHECK(err <= kRelTol * scale + kZeroFieldPx);
    seen = std::max(seen, scale);
  }
  return seen;
}

// ---------------------------------------------------------------- HydroShear, dense reference
struct RefHydroShear {
  const Sensor* sensor;
  const Indenter* ind;
  ParamSet p;
  std::vector<Vec3> u;
  std::vector<double> un, s_last;
  std::vector<char> in;
  Pose X_prev = Pose::Identity();
  bool first = true;

  RefHydroShear(const Sensor& s, const Indenter& i, const ParamSet& params) : sensor(&s), ind(&i), p(params) {
    const std::size_t n = i.samples.p_IS.size();
    u.assign(n, Vec3::Zero());
    un.assign(n, 0);
    s_last.assign(n, 0);
    in.assign(n, 0);
  }

  // The tracker rule of docs/models.md for one point; returns (u, u_n).
  std::pair<Vec3, double> advance(const Vec3& u_old, const Vec3& n, double s_prev, const Vec3& p_prev, double s,
                                  const Vec3& p_now) const {
    const double alpha = s_prev != s ? (std::max(-s, 0.0) - std::max(-s_prev, 0.0)) / (s_prev - s) : 1.0;
    const Vec3 delta = alpha * (p_prev - p_now);
    const Vec3 trial = u_old + delta;
    const double u_n = std::max(trial.dot(n), 0.0);
    Vec3 u_t = trial - trial.dot(n) * n;
    const double cap = p.get("mu") * p.get("E") / p.get("K") * u_n;
    if (u_t.norm() > cap) u_t *= cap / u_t.norm();
    return {u_n * n + u_t, u_n};
  }

  std::vector<Vec2> step(const Pose& X) {
    const auto& P = ind->samples.p_IS;
    const auto& N = ind->samples.n_IS;
    const auto& M = sensor->p_EM;
    const bool normal_ind = p.get("normal") >= 0.5, weight_paper = p.get("weight") >= 0.5;
    const double g_aug = p.get("g_aug");
    const Vec3 shift = g_aug * Vec3(p.get("g_dir_x"), p.get("g_dir_y"), p.get("g_dir_z")).normalized();
    if (first) X_prev = X;
    std::vector<Vec3> pts(P.size());
    std::vector<double> s_now(P.size());
    for (std::size_t i = 0; i < P.size(); ++i) {
      pts[i] = X * P[i];
      s_now[i] = sensor->gel_sdf->value(pts[i]);
      const Vec3 n = normal_ind ? Vec3(-(X.linear() * N[i])) : Vec3::UnitZ();
      if (s_now[i] >= 0) {
        in[i] = 0;
        u[i].setZero();
        un[i] = 0;
        continue;
      }
      const Vec3 p_prev = first ? pts[i] : Vec3(X_prev * P[i]);
      const double s_prev = first ? s_now[i] : sensor->gel_sdf->value(p_prev);
      std::tie(u[i], un[i]) = advance(in[i] ? u[i] : Vec3::Zero(), n, s_prev, p_prev, s_now[i], pts[i]);
      s_last[i] = s_now[i];
      in[i] = 1;
    }
    X_prev = X;
    first = false;
    std::vector<Vec2> shear(M.size(), Vec2::Zero());
    for (std::size_t i = 0; i < P.size(); ++i) {
      const Vec3 n = normal_ind ? Vec3(-(X.linear() * N[i])) : Vec3::UnitZ();
      Vec3 ui = u[i];
      double uni = un[i], phi = s_now[i];
      bool active = in[i];
      if (g_aug > 0) {  // one uncommitted step toward the shifted point
        const double s_aug = sensor->gel_sdf->value(pts[i] + shift);
        active = s_aug < 0;
        if (active)
          std::tie(ui, uni) = advance(in[i] ? u[i] : Vec3::Zero(), n, s_now[i], pts[i], s_aug, pts[i] + shift);
        phi = s_aug;
      }
      if (!active) continue;
      const Vec3 f = p.get("E") * uni * n + p.get("K") * (ui - uni * n);
      const double w = weight_paper ? -phi : p.get("E") * uni;
      const Vec3 a = pts[i] + ui;
      for (std::size_t j = 0; j < M.size(); ++j)
        shear[j] += -w * f.head<2>() * std::exp(-p.get("lambda_s") * (M[j] - a).squaredNorm());
    }
    std::vector<Vec2> out(M.size());
    for (std::size_t j = 0; j < M.size(); ++j) out[j] = p.get("kappa_s") * shear[j];
    for (std::size_t k = 0; k < M.size(); ++k) {
      const double h = std::max(-ind->sdf->value(X.inverse() * M[k]), 0.0);
      for (std::size_t j = 0; j < M.size(); ++j)
        out[j] += p.get("kappa_d") * h * std::exp(-p.get("lambda_d") * (M[j] - M[k]).squaredNorm()) *
                  (M[j] - M[k]).head<2>();
    }
    return out;
  }
};

void check_hydroshear(const ParamSet& params) {
  const Workload& w = workload();
  HydroShearBatch batch(w.sensor, w.peg, w.slots, params);
  std::vector<RefHydroShear> ref(w.slots, RefHydroShear(*w.sensor, *w.peg, params));
  std::vector<Vec2> disp(static_cast<std::size_t>(w.slots) * kMiniMarkers);
  double seen = 0;
  for (int k = 0; k < kBenchMaxSteps; ++k) {
    batch.step(w.X[k], kBenchDt, disp, {});
    std::vector<std::vector<Vec2>> expect;
    for (int s = 0; s < w.slots; ++s) expect.push_back(ref[s].step(w.X[k][s]));
    seen = std::max(seen, compare(disp, expect, k));
    // The sparse tracked list is exactly the dense reference's points in the gel, with the same state.
    for (int s = 0; s < w.slots; ++s) {
      std::size_t n_in = 0;
      for (char c : ref[s].in) n_in += c;
      CHECK(batch.tracked(s).size() == n_in);
      for (const HydroShearPoint& q : batch.tracked(s)) {
        REQUIRE(ref[s].in[q.index]);
        CHECK((q.u_E - ref[s].u[q.index]).norm() <= kRelTol * 1e-3);  // state in metres, mm-sized
      }
    }
  }
  CHECK(seen > 0.01);  // px: the workload presses every pad
}

}  // namespace

TEST_CASE("HydroShear kernel equals the dense reference loop on the workload", "[bench][models]") {
  check_hydroshear(default_params("hydroshear"));
}

TEST_CASE("HydroShear kernel equals the dense reference with the paper options and augmentation", "[bench][models]") {
  // weight = paper, normal = indenter, a 0.25 mm augmentation out of the plane and along it: the cull
  // must keep the clusters that only the shifted points bring into the gel.
  ParamSet p = default_params("hydroshear");
  p.set("weight", 1);
  p.set("normal", 1);
  p.set("g_aug", 0.25e-3);
  p.set("g_dir_x", -1);
  p.set("g_dir_z", -1);
  check_hydroshear(p);
}

TEST_CASE("GaussianAxis recurrence equals one exp per coordinate", "[bench][models]") {
  // 9 markers at the workload pitch; anchors inside, beyond both ends, and a rate so large that the
  // recurrence would underflow (then it falls back to std::exp per coordinate).
  constexpr double kPitch = 2.0922e-3;
  std::vector<double> xs;
  for (int c = 0; c < 9; ++c) xs.push_back((c - 4) * kPitch);
  for (double lambda : {10800.0, 2e5, 1e7})
    for (double a : {0.0, 1.3e-3, -9.1e-3, 0.03}) {
      const GaussianAxis g(xs, lambda);
      double e[9];
      g.eval(a, e);
      for (int c = 0; c < 9; ++c) {
        const double expect = std::exp(-lambda * (xs[c] - a) * (xs[c] - a));
        INFO("lambda " << lambda << " a " << a << " c " << c);
        CHECK(std::abs(e[c] - expect) <= kRelTol * expect + 1e-300);
      }
    }
}

// ---------------------------------------------------------------- FOTS (both), reference
namespace {

Vec2 rot(const Vec2& d, double th) {
  return {std::cos(th) * d.x() - std::sin(th) * d.y(), std::sin(th) * d.x() + std::cos(th) * d.y()};
}

struct RefFots {
  bool original;
  const Sensor* sensor;
  const Indenter* ind;
  ParamSet p;
  bool in_contact = false, have_prev = false, grasping = false;
  Pose X_ref = Pose::Identity(), X_prev = Pose::Identity(), X_start = Pose::Identity();
  Vec3 c_I = Vec3::Zero(), se2_ref = Vec3::Zero();
  Quat q_last = Quat::Identity();

  std::vector<Vec2> step(const Pose& X) {
    const auto& M = sensor->p_EM;
    const int nm = static_cast<int>(M.size());
    std::vector<double> h(nm);
    Vec3 c_sum = Vec3::Zero();
    int n_in = 0;
    for (int k = 0; k < nm; ++k) {
      const Vec3 m_I = X.inverse() * M[k];
      h[k] = std::max(-ind->sdf->value(m_I), 0.0);
      if (h[k] > 0) {
        ++n_in;
        c_sum += m_I;
      }
    }
    std::vector<Vec2> out(nm, Vec2::Zero());
    return original ? step_original(X, h, n_in, out) : step_reimpl(X, h, n_in, c_sum, out);
  }

  std::vector<Vec2> step_original(const Pose& X, const std::vector<double>& h, int n_in, std::vector<Vec2>& out) {
    const int nm = static_cast<int>(h.size());
    if (n_in == 0) {
      in_contact = false;
      return out;
    }
    if (!in_contact) {
      in_contact = true;
      X_ref = X;
    }
    const double ppm = p.get("px_per_mm") * 1e3;
    const Vec2 centre = sensor->camera.principal_px;
    std::vector<Vec2> m(nm), x(nm);
    for (int j = 0; j < nm; ++j) x[j] = m[j] = centre + sensor->p_EM[j].head<2>() * ppm;
    for (int j = 0; j < nm; ++j)
      for (int k = 0; k < nm; ++k)
        if (h[k] > 0) x[j] += h[k] * 1e3 * std::exp(-p.get("lambda_d") * (m[j] - m[k]).squaredNorm()) * (m[j] - m[k]);
    const Vec3 t0 = X_ref.translation(), t1 = X.translation();
    const Vec2 G(std::trunc(t0.x() * ppm + centre.x()), std::trunc(t0.y() * ppm + centre.y()));
    const Vec2 s(std::trunc((t1.x() - t0.x()) * ppm), std::trunc((t1.y() - t0.y()) * ppm));
    for (int j = 0; j < nm; ++j) x[j] += s * std::exp(-p.get("lambda_s") * (x[j] - G).squaredNorm());
    const double clip = p.get("twist_clip_deg") * std::numbers::pi / 180;
    const double th = std::clamp(twist_about_z(X.linear() * X_ref.linear().transpose()), -clip, clip);
    for (int j = 0; j < nm; ++j) {
      const Vec2 d = x[j] - G;
      x[j] += (rot(d, th) - d) * std::exp(-p.get("lambda_t") * d.squaredNorm());
    }
    for (int j = 0; j < nm; ++j) out[j] = x[j] - m[j];
    return out;
  }

  Vec3 se2(const Pose& X, bool continuity) {
    const Pose X_EC = X * Eigen::Translation3d(c_I);
    Quat q(X_EC.linear());
    if (continuity ? q.coeffs().dot(q_last.coeffs()) < 0 : q.w() < 0) q.coeffs() *= -1;
    q_last = q;
    const double vn = q.vec().norm();
    const double rz = vn == 0 ? 0 : 2 * std::atan2(vn, q.w()) * q.z() / vn;
    return {X_EC.translation().x(), X_EC.translation().y(), rz};
  }

  std::vector<Vec2> step_reimpl(const Pose& X, const std::vector<double>& h, int n_in, const Vec3& c_sum,
                                std::vector<Vec2>& out) {
    const auto& M = sensor->p_EM;
    const int nm = static_cast<int>(M.size());
    if (n_in == 0) {
      in_contact = false;
      have_prev = true;
      X_prev = X;
      return out;
    }
    // The anchor follows the patch centre until the pose leaves the normal approach (the authors' grasp):
    // the first pose that differs from the history's start by more than a translation along z_E.
    if (!in_contact) {
      in_contact = true;
      grasping = p.get("anchor_grasp") >= 0.5;
      X_start = have_prev ? X_prev : X;
      c_I = c_sum / n_in;
      se2_ref = se2(X_start, false);
    } else if (grasping) {
      const bool normal = (X.translation() - X_start.translation()).head<2>().norm() <= 1e-9 &&
                          Eigen::AngleAxisd(X.linear() * X_start.linear().transpose()).angle() <= 1e-9;
      if (normal) {
        c_I = c_sum / n_in;
        se2_ref = se2(X_start, false);
      } else {
        grasping = false;
      }
    }
    const Vec3 now = se2(X, true);
    const Vec2 dxy = now.head<2>() - se2_ref.head<2>();
    const double dth = std::clamp(now.z() - se2_ref.z(), -std::numbers::pi, std::numbers::pi);
    for (int j = 0; j < nm; ++j) {
      const Vec2 d = M[j].head<2>() - se2_ref.head<2>();
      out[j] = p.get("kappa_s") * dxy * std::exp(-p.get("lambda_s") * d.norm()) +
               p.get("kappa_t") * (rot(d, dth) - d) * std::exp(-p.get("lambda_t") * d.norm());
      for (int k = 0; k < nm; ++k)
        out[j] += p.get("kappa_d") * h[k] * std::exp(-p.get("lambda_d") * (M[j] - M[k]).norm()) *
                  (M[j] - M[k]).head<2>();
    }
    X_prev = X;
    have_prev = true;
    return out;
  }
};

void check_fots(FotsVariant variant) {
  const Workload& w = workload();
  const std::string id = variant == FotsVariant::kOriginal ? "fots" : "fots-reimpl";
  FotsBatch batch(variant, w.sensor, w.peg, w.slots, default_params(id));
  std::vector<RefFots> ref(w.slots,
                           RefFots{variant == FotsVariant::kOriginal, w.sensor.get(), w.peg.get(), default_params(id)});
  std::vector<Vec2> disp(static_cast<std::size_t>(w.slots) * kMiniMarkers);
  double seen = 0;
  for (int k = 0; k < kBenchMaxSteps; ++k) {
    batch.step(w.X[k], kBenchDt, disp, {});
    std::vector<std::vector<Vec2>> expect;
    for (int s = 0; s < w.slots; ++s) expect.push_back(ref[s].step(w.X[k][s]));
    seen = std::max(seen, compare(disp, expect, k));
  }
  CHECK(seen > 0.01);
}

// ---------------------------------------------------------------- TacSL, reference
struct RefTacsl {
  bool normalized;
  const Sensor* sensor;
  const Indenter* ind;
  ParamSet p;
  bool have_prev = false;
  Pose X_prev = Pose::Identity();

  std::vector<Vec2> step(const Pose& X, double dt) {
    const auto& M = sensor->p_EM;
    std::vector<Vec2> out(M.size(), Vec2::Zero());
    for (std::size_t j = 0; j < M.size(); ++j) {
      const Vec3 p_I = X.inverse() * M[j];
      Vec3 grad;
      const double d = std::max(-ind->sdf->value_and_gradient(p_I, &grad), 0.0);
      if (d <= 0) continue;
      const Vec3 n_I = grad.normalized(), n = X.linear() * n_I;
      Vec3 f_t = Vec3::Zero();
      if (have_prev && dt > 0) {
        const Vec3 c_I = p_I + d * n_I;
        const Vec3 v = -(X * c_I - X_prev * c_I) / dt;
        const Vec3 v_t = v - n * n.dot(v);
        f_t = -std::min(p.get("kt") * v_t.norm(), p.get("mu") * p.get("kn") * d) * v_t / std::max(v_t.norm(), 1e-9);
      }
      const Vec2 shear = (p.get("include_normal") >= 0.5 ? Vec3(p.get("kn") * d * n + f_t) : f_t).head<2>();
      const double g = p.get("gain_px");
      out[j] = normalized ? (shear.norm() > 1e-4 ? Vec2(g * shear / shear.norm()) : Vec2::Zero()) : Vec2(g * shear);
    }
    X_prev = X;
    have_prev = true;
    return out;
  }
};

void check_tacsl(bool normalized) {
  const Workload& w = workload();
  const std::string id = normalized ? "tacsl-normalized" : "tacsl";
  TacslBatch batch(normalized, w.sensor, w.peg, w.slots, default_params(id));
  std::vector<RefTacsl> ref(w.slots, RefTacsl{normalized, w.sensor.get(), w.peg.get(), default_params(id)});
  std::vector<Vec2> disp(static_cast<std::size_t>(w.slots) * kMiniMarkers);
  double seen = 0;
  for (int k = 0; k < kBenchMaxSteps; ++k) {
    batch.step(w.X[k], kBenchDt, disp, {});
    std::vector<std::vector<Vec2>> expect;
    for (int s = 0; s < w.slots; ++s) expect.push_back(ref[s].step(w.X[k][s], kBenchDt));
    seen = std::max(seen, compare(disp, expect, k));
  }
  CHECK(seen > 0.01);
}

}  // namespace

TEST_CASE("FOTS kernels equal the reference loops on the workload", "[bench][models]") {
  check_fots(FotsVariant::kOriginal);
  check_fots(FotsVariant::kReimpl);
}

TEST_CASE("TacSL kernels equal the reference loops on the workload", "[bench][models]") {
  check_tacsl(false);
  check_tacsl(true);
}

TEST_CASE("bench run: statistics over k = 3..S-1 and one result per model", "[bench]") {
  // Median of an even count is the mean of the middle two: {4, 1, 3, 2} -> (2 + 3) / 2 = 2.5.
  const Stats s = bench_stats({4, 1, 3, 2});
  CHECK(s.median == 2.5);
  CHECK(s.min == 1);
  CHECK(s.max == 4);
  CHECK_THROWS_AS(bench_stats({}), std::invalid_argument);
  CHECK_THROWS_AS(BenchWorkload("nope", 2), std::invalid_argument);
  CHECK_THROWS_AS(BenchWorkload("tacsl", 2, 3), std::invalid_argument);   // no timed step
  CHECK_THROWS_AS(BenchWorkload("tacsl", 2, 51), std::invalid_argument);  // beyond the trajectory
  for (const auto& id : bench_model_ids()) {
    BenchWorkload w(id, 2, 8);
    const BenchResult r = w.run(true);
    INFO(id);
    CHECK(r.slots == 4);
    CHECK(r.step_ms.size() == 8);
    CHECK(r.timed_steps == 5);
    CHECK(r.min_ms <= r.median_ms);
    CHECK(r.median_ms <= r.max_ms);
    CHECK(r.checksum > 0);  // the pads are pressed by step 7
    double phases = 0;
    for (double v : r.phase_cpu_ms) phases += v;
    CHECK(phases > 0);
    // The run is repeatable: a reset makes the second run compute the same last field.
    CHECK(w.run(false).checksum == r.checksum);
  }
}

TEST_CASE("exp_in_place equals std::exp to a few ulp over the exponent range", "[bench][models]") {
  // Relative agreement: the reduction and a degree-12 Taylor polynomial round a few times (~1e-15).
  constexpr double kExpTol = 1e-14;
  std::vector<double> x;
  for (double v = -700; v <= 700; v += 0.37) x.push_back(v);
  for (double v : {0.0, -1e-300, 1e-12, -0.5 * std::numbers::ln2, 0.5 * std::numbers::ln2}) x.push_back(v);
  std::vector<double> e = x;
  exp_in_place(e.data(), static_cast<int>(e.size()));
  for (std::size_t i = 0; i < x.size(); ++i) {
    INFO("x = " << x[i]);
    CHECK(std::abs(e[i] - std::exp(x[i])) <= kExpTol * std::exp(x[i]));
  }
}

}  // namespace test_model_kernels
