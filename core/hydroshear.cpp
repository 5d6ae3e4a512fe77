#include "core/hydroshear.hpp"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace sb {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Points per cluster of the cull: small enough that a cluster's sphere hugs the surface (about 1.3 mm
// for 0.75 mm spacing), large enough that the per-cluster test is cheap next to the points it skips.
constexpr int kClusterLeaf = 8;
constexpr int kClusterGroup = 8;  // clusters per group of the two-level cull
// Metres added to the cull bound so rounding of the cluster test can never drop a point whose own
// transform would give z_E < cull_z_.
constexpr double kCullMargin = 1e-9;
// Tasks of the slot loop: slots per task (a slot costs a few microseconds).
constexpr int kSlotGrain = 16;
const double kDefaultPxPerMetre = Camera{}.px_per_metre();  // 1 / 0.0634 mm = 15772.9 px/m

}  // namespace

std::vector<ParamSpec> hydroshear_param_specs() {
  return {
      {"lambda_d", "m^-2", 20000, 1e2, 1e7, "dilation Gaussian rate on squared distance (authors' RL config)", true},
      {"lambda_s", "m^-2", 10800, 1e2, 1e7, "shear Gaussian rate on squared distance (authors' RL config)", true},
      {"mu", "", 0.5, 0, 5, "friction-cone ratio |f_t| <= mu f_n"},
      {"kappa_d", "px/m", kDefaultPxPerMetre, 1, 1e9,
       "dilation scale; default the GelSight Mini camera 1/0.0634 mm (authors: 1/0.065 mm = 15384.6)", true},
      {"kappa_s", "px/m", kDefaultPxPerMetre, 1, 1e9,
       "shear scale; default the GelSight Mini camera 1/0.0634 mm (authors: 1/0.065 mm = 15384.6)", true},
      {"K", "", 1, 1e-3, 1e6, "tangential stiffness gain (authors K = A = 1: state in metres)", true},
      {"E", "", 1, 1e-3, 1e6, "normal stiffness gain (authors E = A = 1: state in metres)", true},
      {"g_aug", "m", 0, 0, 5e-3, "gravity augmentation: virtual uncommitted shift of the indenter (authors' RL: 0.25 mm)"},
      {"g_dir_x", "", -1, -1, 1, "x_E component of the augmentation direction (normalised)"},
      {"g_dir_y", "", 0, -1, 1, "y_E component of the augmentation direction"},
      {"g_dir_z", "", 0, -1, 1, "z_E component of the augmentation direction"},
      {"weight", "", 0, 0, 1, "shear weight: 0 = accumulated normal state f_n (authors' code), 1 = depth -phi_E (paper)"},
      {"normal", "", 0, 0, 1, "normal of the n/t split: 0 = elastomer +z (authors' code), 1 = indenter normal (paper)"},
      {"flat_pad_fast", "", 1, 0, 1, "1: exact analytic phi_E for a flat pad; 0: always query sensor.gel_sdf"},
  };
}

HydroShearParams HydroShearParams::from(const ParamSet& p) {
  HydroShearParams k;
  k.lambda_d = p.get("lambda_d");
  k.lambda_s = p.get("lambda_s");
  k.mu = p.get("mu");
  k.kappa_d = p.get("kappa_d");
  k.kappa_s = p.get("kappa_s");
  k.K = p.get("K");
  k.E = p.get("E");
  k.g_aug = p.get("g_aug");
  const Vec3 dir(p.get("g_dir_x"), p.get("g_dir_y"), p.get("g_dir_z"));
  if (k.g_aug > 0 && dir.norm() == 0)
    throw std::invalid_argument("hydroshear: g_aug > 0 needs a non-zero direction (g_dir_x, g_dir_y, g_dir_z)");
  k.g_dir_E = dir.norm() > 0 ? Vec3(dir.normalized()) : Vec3::Zero();
  k.weight_paper = param_flag(p, "weight");
  k.normal_indenter = param_flag(p, "normal");
  k.flat_pad_fast = param_flag(p, "flat_pad_fast");
  return k;
}

// Per-thread buffers, reused across steps (no allocation once the largest contact has been seen).
struct HydroShearBatch::Scratch {
  // Candidates: points of the clusters that can reach the gel, in point order, with phi_E < 0 now or
  // (augmentation) at the shifted pose.
  std::vector<int> pos;
  std::vector<Vec3> p;
  std::vector<double> s, s_aug;
  std::vector<HydroShearPoint> next, out;
  std::vector<Vec3> p_of_field;            // the real point o_i of each field point (anchor = o_i + u_i)
  std::vector<Vec3> m_I;
  std::vector<double> phi_I;
  std::vector<double> ex, ey;
  std::vector<double> shear_x, shear_y;    // per marker
  // Batched shear: per fast point its (vx, vy), 3 exponents then exps, and the GEMM operands.
  std::vector<Vec2> v;
  std::vector<double> args, w_rows, ex_rows, s_mat;
};
struct HydroShearBatch::ScratchPool {
  tbb::enumerable_thread_specific<Scratch> local;
};

HydroShearBatch::HydroShearBatch(std::shared_ptr<const Sensor> sensor, std::shared_ptr<const Indenter> indenter,
                                 int slots, const ParamSet& params)
    : sensor_(std::move(sensor)), indenter_(std::move(indenter)), slots_(std::max(slots, 0)),
      pool_(std::make_unique<ScratchPool>()) {
  if (!sensor_ || !sensor_->gel_sdf) throw std::invalid_argument("hydroshear: sensor with a gel SDF required");
  if (!indenter_ || !indenter_->sdf) throw std::invalid_argument("hydroshear: indenter with an SDF required");
  if (indenter_->samples.p_IS.empty()) throw std::invalid_argument("hydroshear: indenter has no surface samples");
  if (indenter_->samples.n_IS.size() != indenter_->samples.p_IS.size())
    throw std::invalid_argument("hydroshear: indenter samples need one normal per point");
  grid_ = detect_marker_grid(sensor_->p_EM);
  marker_z_max_ = -kInf;
  for (const Vec3& m : sensor_->p_EM) marker_z_max_ = std::max(marker_z_max_, m.z());
  build_clusters();
  set_params(params);
}

HydroShearBatch::~HydroShearBatch() = default;
HydroShearBatch::HydroShearBatch(HydroShearBatch&&) noexcept = default;
HydroShearBatch::HydroShearBatch(const HydroShearBatch& o)
    : sensor_(o.sensor_), indenter_(o.indenter_), params_(o.params_), k_(o.k_), flat_(o.flat_), pad_(o.pad_),
      grid_(o.grid_), gauss_x_(o.gauss_x_), gauss_y_(o.gauss_y_), dil_x_(o.dil_x_), dil_y_(o.dil_y_),
      marker_z_max_(o.marker_z_max_), perm_(o.perm_), pos_of_(o.pos_of_), p_I_(o.p_I_), n_I_(o.n_I_),
      clusters_(o.clusters_), groups_(o.groups_), cull_z_(o.cull_z_), cull_(o.cull_), slots_(o.slots_),
      pool_(std::make_unique<ScratchPool>()), profile_(nullptr) {}

// Recursive median split along the longest axis of the bounding box until kClusterLeaf points remain:
// spatially compact clusters whatever the sample order.
void HydroShearBatch::build_clusters() {
  const auto& P = indenter_->samples.p_IS;
  const int n = static_cast<int>(P.size());
  perm_.resize(n);
  std::iota(perm_.begin(), perm_.end(), 0);
  clusters_.clear();
  auto split = [&](auto&& self, int begin, int end) -> void {
    Eigen::AlignedBox3d box;
    for (int i = begin; i < end; ++i) box.extend(P[perm_[i]]);
    if (end - begin <= kClusterLeaf) {
      Vec3 c = Vec3::Zero();
      for (int i = begin; i < end; ++i) c += P[perm_[i]];
      c /= end - begin;
      double r = 0;
      for (int i = begin; i < end; ++i) r = std::max(r, (P[perm_[i]] - c).norm());
      clusters_.push_back({begin, end, c, r});
      return;
    }
    int axis = 0;
    box.sizes().maxCoeff(&axis);
    const int mid = begin + (end - begin) / 2;
    std::nth_element(perm_.begin() + begin, perm_.begin() + mid, perm_.begin() + end,
                     [&](int a, int b) { return P[a][axis] < P[b][axis] || (P[a][axis] == P[b][axis] && a < b); });
    self(self, begin, mid);
    self(self, mid, end);
  };
  split(split, 0, n);
  groups_.clear();
  const int nc = static_cast<int>(clusters_.size());
  for (int g = 0; g < nc; g += kClusterGroup) {
    const int g_end = std::min(g + kClusterGroup, nc);
    const int p_begin = clusters_[g].begin, p_end = clusters_[g_end - 1].end;
    Vec3 c = Vec3::Zero();
    for (int i = p_begin; i < p_end; ++i) c += P[perm_[i]];
    c /= p_end - p_begin;
    double r = 0;
    for (int i = p_begin; i < p_end; ++i) r = std::max(r, (P[perm_[i]] - c).norm());
    groups_.push_back({g, g_end, c, r});
  }
  pos_of_.resize(n);
  p_I_.resize(n);
  n_I_.resize(n);
  for (int pos = 0; pos < n; ++pos) {
    pos_of_[perm_[pos]] = pos;
    p_I_[pos] = P[perm_[pos]];
    n_I_[pos] = indenter_->samples.n_IS[perm_[pos]];
  }
}

void HydroShearBatch::set_params(const ParamSet& params) {
  k_ = HydroShearParams::from(params);
  params_ = params;
  flat_ = k_.flat_pad_fast && flat_pad_of(*sensor_, &pad_);
  // The flat pad occupies z_E <= 0, so phi_E(p) >= z_E: a point at z_E >= 0 is never in the gel. A general
  // gel SDF (a mesh, a nearest-voxel cache) may be negative above its surface, so it is not culled.
  cull_ = flat_;
  cull_z_ = 0;
  const auto& m = sensor_->p_EM;
  const int n = static_cast<int>(m.size());
  dil_x_.resize(static_cast<std::size_t>(n) * n);
  dil_y_.resize(static_cast<std::size_t>(n) * n);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j) {
      const double w = std::exp(-k_.lambda_d * (m[j] - m[k]).squaredNorm());
      dil_x_[k * n + j] = w * (m[j] - m[k]).x();
      dil_y_[k * n + j] = w * (m[j] - m[k]).y();
    }
  if (grid_.is_grid) {
    gauss_x_ = GaussianAxis(grid_.xs, k_.lambda_s);
    gauss_y_ = GaussianAxis(grid_.ys, k_.lambda_s);
  }
}

void HydroShearBatch::reset() {
  for (int i = 0; i < slots(); ++i) reset_slot(i);
}

void HydroShearBatch::reset_slot(int slot) {
  Slot& s = slots_.at(slot);
  s.points.clear();
  s.first = true;
  s.X_prev = Pose::Identity();
}


// Normal of the n/t split, pointing out of the gel: +z_E (code) or minus the indenter's outward normal
// (paper).
Vec3 HydroShearBatch::n_hat_at(int pos, const Mat3& R_EI) const {
  return k_.normal_indenter ? Vec3(-(R_EI * n_I_[pos])) : Vec3::UnitZ();
}

// One point's tracker step from (s_prev, p_prev) to (s, p), s < 0 (the caller drops points outside).
HydroShearPoint HydroShearBatch::advance(const HydroShearPoint* old, int index, const Vec3& n_hat, double s_prev,
                                         const Vec3& p_prev, double s, const Vec3& p) const {
  // In-gel fraction of the segment. 0/0 (s unchanged) falls back to the authors' -(sign(s) - 1)/2,
  // which is 1 here since s < 0.
  const double den = s_prev - s;
  const double alpha = den != 0 ? (std::max(-s, 0.0) - std::max(-s_prev, 0.0)) / den : 1.0;
  const Vec3 delta = alpha * (p_prev - p);
  const Vec3 u_old = old ? old->u_E : Vec3::Zero();
  const double un_trial = u_old.dot(n_hat) + delta.dot(n_hat);
  const Vec3 ut_trial = (u_old - u_old.dot(n_hat) * n_hat) + (delta - delta.dot(n_hat) * n_hat);
  const double un = std::max(un_trial, 0.0);
  // The cone |K u_t| <= mu |E u_n| on the metre-valued state.
  const double cap = k_.mu * k_.E / k_.K * un;
  const double ut_norm = ut_trial.norm();
  HydroShearPoint q;
  q.index = index;
  q.phi_E = s;
  q.u_n = un;
  if (ut_norm > cap) {
    // Exact projection; the authors divide by |f_t| + 1e-8 m (a relative change <= 1e-4 for 0.1 mm).
    q.u_E = un * n_hat + ut_trial * (cap / ut_norm);
    q.state = PointState::Slip;
  } else {
    q.u_E = un * n_hat + ut_trial;
    q.state = PointState::Stick;
  }
  return q;
}

void HydroShearBatch::step(std::span<const Pose> X_EI, double dt, std::span<Vec2> disp_px,
                           std::span<FieldOutput> diagnostics) {
  const int n = slots();
  const std::size_t nm = sensor_->p_EM.size();
  if (static_cast<int>(X_EI.size()) != n || disp_px.size() != n * nm)
    throw std::invalid_argument("hydroshear: step needs one pose per slot and markers() displacements per slot");
  if (!diagnostics.empty() && static_cast<int>(diagnostics.size()) != n)
    throw std::invalid_argument("hydroshear: diagnostics must be empty or one per slot");
  for (const Pose& X : X_EI) require_finite_pose(X, "hydroshear");
  auto body = [&](const tbb::blocked_range<int>& r) {
    Scratch& scratch = pool_->local.local();
    PhaseClock clock(profile_);
    for (int i = r.begin(); i < r.end(); ++i)
      step_slot(slots_[i], X_EI[i], &disp_px[i * nm], diagnostics.empty() ? nullptr : &diagnostics[i], scratch,
                clock);
  };
  if (n == 1) {
    body(tbb::blocked_range<int>(0, 1));
  } else {
    tbb::parallel_for(tbb::blocked_range<int>(0, n, kSlotGrain), body);
  }
}

// The points that may be in the gel now (or at the augmented pose), with o_i in E and phi_E(o_i).
void HydroShearBatch::gather_candidates(const Pose& X_EI, Scratch& sc) const {
  const Mat3 R = X_EI.linear();
  const Vec3 t = X_EI.translation();
  const bool aug = k_.g_aug > 0;
  const Vec3 shift = k_.g_aug * k_.g_dir_E;
  // z_E of a cluster centre is R.row(2) c + t_z; its points are within radius of it. With the
  // augmentation the shifted points must be tested too, so the lower of the two heights counts.
  const Vec3 r_z = R.row(2).transpose();
  const double z_shift_down = aug ? std::min(shift.z(), 0.0) : 0.0;
  sc.pos.clear();
  sc.p.clear();
  sc.s.clear();
  sc.s_aug.clear();
  // A sphere (centre c, radius r in I) is entirely above the cull plane, also after the shift.
  auto above = [&](const Cluster& c) {
    return cull_ && r_z.dot(c.centre_I) + t.z() + z_shift_down - c.radius > cull_z_ + kCullMargin;
  };
  auto gather = [&](const Cluster& c) {
    for (int pos = c.begin; pos < c.end; ++pos) {
      // Most points of a kept cluster are still above the pad: z_E >= 0 means phi_E >= 0.
      if (cull_ && !aug && r_z.dot(p_I_[pos]) + t.z() >= cull_z_) continue;
      const Vec3 p = R * p_I_[pos] + t;
      const double s = phi_E(p);
      const double s_aug = aug ? phi_E(p + shift) : kInf;
      if (s >= 0 && s_aug >= 0) continue;
      sc.pos.push_back(pos);
      sc.p.push_back(p);
      sc.s.push_back(s);
      if (aug) sc.s_aug.push_back(s_aug);
    }
  };
  for (const Cluster& g : groups_) {
    if (above(g)) continue;
    for (int ci = g.begin; ci < g.end; ++ci)
      if (!above(clusters_[ci])) gather(clusters_[ci]);
  }
}

// The tracker step: candidates inside the gel advance from their old state (or from zero when they
// enter); every other point's state is reset to zero, i.e. dropped from the sparse list.
void HydroShearBatch::commit_state(Slot& slot, const Pose& X_EI, Scratch& sc) const {
  const Mat3 R = X_EI.linear();
  // The authors' first call after a reset sets prev = current, so penetration already present then
  // is lost (BASELINES §3.5).
  if (slot.first) slot.X_prev = X_EI;
  sc.next.clear();
  sc.p_of_field.clear();  // the real point of each committed point, for the anchors
  std::size_t k = 0;
  const std::size_t nc = sc.pos.size();
  for (std::size_t c = 0; c < nc; ++c) {
    if (sc.s[c] >= 0) continue;
    const int pos = sc.pos[c];
    while (k < slot.points.size() && pos_of_[slot.points[k].index] < pos) ++k;
    const HydroShearPoint* old =
        k < slot.points.size() && pos_of_[slot.points[k].index] == pos ? &slot.points[k] : nullptr;
    const Vec3& p = sc.p[c];
    const Vec3 p_prev = slot.first ? p : Vec3(slot.X_prev * p_I_[pos]);
    // A point not tracked last step was outside then; its exact phi_E is needed for alpha.
    const double s_prev = slot.first ? sc.s[c] : old ? old->phi_E : phi_E(p_prev);
    sc.next.push_back(advance(old, perm_[pos], n_hat_at(pos, R), s_prev, p_prev, sc.s[c], p));
    sc.p_of_field.push_back(p);
  }
  slot.points.swap(sc.next);
  slot.X_prev = X_EI;
  slot.first = false;
}

// The state the field uses with the augmentation: one virtual, uncommitted step from the committed
// state toward the points shifted by g_aug dir.
const std::vector<HydroShearPoint>& HydroShearBatch::augmented_state(const Slot& slot, const Pose& X_EI,
                                                                    Scratch& sc) const {
  const Mat3 R = X_EI.linear();
  const Vec3 shift = k_.g_aug * k_.g_dir_E;
  sc.out.clear();
  sc.p_of_field.clear();
  std::size_t k = 0;
  for (std::size_t c = 0; c < sc.pos.size(); ++c) {
    const int pos = sc.pos[c];
    while (k < slot.points.size() && pos_of_[slot.points[k].index] < pos) ++k;
    if (sc.s_aug[c] >= 0) continue;
    const HydroShearPoint* old =
        k < slot.points.size() && pos_of_[slot.points[k].index] == pos ? &slot.points[k] : nullptr;
    sc.out.push_back(advance(old, perm_[pos], n_hat_at(pos, R), sc.s[c], sc.p[c], sc.s_aug[c], sc.p[c] + shift));
    sc.p_of_field.push_back(sc.p[c]);
  }
  return sc.out;
}

// M_s(m_j) = sum_i w_i (-f_i^xy) exp(-lambda_s |m_j - a_i|^2), anchor a_i = o_i + u_i at the real (not
// shifted) point, as the authors' code; the 3-D distance (code). Unscaled (kappa_s applied on output).
//
// On a uniform marker grid the Gaussian of point i at marker (r, c) is
//   exp(-l |m_rc - a_i|^2) = E_i * X_i[c] * Y_i[r],  E_i = exp(-l (d0x^2 + d0y^2 + dz^2)),
// with X_i, Y_i the per-axis ratio recurrences (GaussianAxis): 3 exps per point, batched through
// exp_in_place. The sum over points is then one small matrix product (add_outer_products)
//   S (2 rows x cols) = W^T X,  W_i = (vx_i E_i Y_i[r], vy_i E_i Y_i[r]),  X_i = (X_i[c]).
void HydroShearBatch::shear_sum(const std::vector<HydroShearPoint>& points, const Pose& X_EI, Scratch& sc) const {
  // Exponent budget of the factored form: every partial product stays above e^-kMaxTotalExponent,
  // far from underflow (e^-708); a point beyond it uses one exp per axis coordinate instead.
  constexpr double kMaxTotalExponent = 650;
  const Mat3 R = X_EI.linear();
  const auto& M = sensor_->p_EM;
  const int nm = static_cast<int>(M.size());
  sc.shear_x.assign(nm, 0.0);
  sc.shear_y.assign(nm, 0.0);
  const double ls = k_.lambda_s;
  double* sx = sc.shear_x.data();
  double* sy = sc.shear_y.data();
  const bool factored = grid_.is_grid && gauss_x_.uniform() && gauss_y_.uniform();
  const int rows = grid_.rows, cols = grid_.cols;
  if (grid_.is_grid) {
    sc.ex.resize(cols);
    sc.ey.resize(rows);
  }
  sc.v.clear();
  sc.args.clear();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const HydroShearPoint& q = points[i];
    const Vec3 n_hat = n_hat_at(pos_of_[q.index], R);
    const Vec3 ut = q.u_E - q.u_n * n_hat;
    const Vec3 f = k_.E * q.u_n * n_hat + k_.K * ut;
    const double w = k_.weight_paper ? -q.phi_E : k_.E * q.u_n;
    const double vx = -w * f.x(), vy = -w * f.y();
    if (vx == 0 && vy == 0) continue;
    const Vec3 a = sc.p_of_field[i] + q.u_E;
    if (factored) {
      const double lz = ls * (grid_.z0 - a.z()) * (grid_.z0 - a.z());
      if (gauss_x_.max_exponent(a.x()) + gauss_y_.max_exponent(a.y()) + lz <= kMaxTotalExponent) {
        sc.v.emplace_back(vx, vy);
        sc.args.push_back(gauss_x_.lead_exponent(a.x()) + gauss_y_.lead_exponent(a.y()) - lz);
        sc.args.push_back(gauss_x_.ratio_exponent(a.x()));
        sc.args.push_back(gauss_y_.ratio_exponent(a.y()));
        continue;
      }
    }
    if (grid_.is_grid) {
      gauss_x_.eval(a.x(), sc.ex.data());
      gauss_y_.eval(a.y(), sc.ey.data());
      const double ez = std::exp(-ls * (grid_.z0 - a.z()) * (grid_.z0 - a.z()));
      for (int r = 0; r < rows; ++r)
        for (int c = 0; c < cols; ++c) {
          const double e = ez * sc.ey[r] * sc.ex[c];
          sx[r * cols + c] += vx * e;
          sy[r * cols + c] += vy * e;
        }
    } else {
      for (int j = 0; j < nm; ++j) {
        const double e = std::exp(-ls * (M[j] - a).squaredNorm());
        sx[j] += vx * e;
        sy[j] += vy * e;
      }
    }
  }
  const int m = static_cast<int>(sc.v.size());
  if (m == 0) return;
  exp_in_place(sc.args.data(), 3 * m);
  const int stride = (cols + 3) / 4 * 4;  // whole 4-double vectors per row
  // kOverreadPad doubles past the operands: the vectorised add_outer_products (GCC, AVX2) may load a
  // full vector that straddles the end of W or X (seen as a fault at a page boundary without it).
  constexpr std::size_t kOverreadPad = 64;
  sc.w_rows.resize(static_cast<std::size_t>(m) * 2 * rows + kOverreadPad);
  // Not zeroed: the padding columns (cols..stride) only feed S's padding columns, which are discarded.
  sc.ex_rows.resize(static_cast<std::size_t>(m) * stride + kOverreadPad);
  sc.s_mat.assign(static_cast<std::size_t>(2 * rows) * stride, 0.0);
  for (int i = 0; i < m; ++i) {
    const double E = sc.args[3 * i];
    gauss_x_.ratios(sc.args[3 * i + 1], &sc.ex_rows[static_cast<std::size_t>(i) * stride]);
    gauss_y_.ratios(sc.args[3 * i + 2], sc.ey.data());
    double* wr = &sc.w_rows[static_cast<std::size_t>(i) * 2 * rows];
    for (int r = 0; r < rows; ++r) {
      const double g = E * sc.ey[r];
      wr[r] = sc.v[i].x() * g;
      wr[rows + r] = sc.v[i].y() * g;
    }
  }
  add_outer_products(sc.w_rows.data(), 2 * rows, sc.ex_rows.data(), stride, m, sc.s_mat.data());
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      sx[r * cols + c] += sc.s_mat[r * stride + c];
      sy[r * cols + c] += sc.s_mat[(rows + r) * stride + c];
    }
}

// Output: kappa_s M_s plus the dilation from markers inside the indenter, h_k = relu(-phi_I(X_IE m_k)).
void HydroShearBatch::dilation(const Pose& X_EI, Vec2* disp, Scratch& sc, PhaseClock& clock) const {
  const auto& M = sensor_->p_EM;
  const int nm = static_cast<int>(M.size());
  for (int j = 0; j < nm; ++j) disp[j] = k_.kappa_s * Vec2(sc.shear_x[j], sc.shear_y[j]);
  sc.phi_I.assign(nm, kInf);
  // No marker can be inside the indenter when its SDF bounds (a box in I) lie above every marker.
  const Eigen::AlignedBox3d B = indenter_->sdf->bounds();
  const Mat3 R = X_EI.linear();
  const Vec3 t = X_EI.translation();
  const Vec3 half = 0.5 * B.sizes();
  const double z_low = (R * B.center() + t).z() - R.row(2).cwiseAbs().dot(half);
  if (z_low > marker_z_max_) return;
  sc.m_I.resize(nm);
  const Mat3 Rt = R.transpose();
  for (int j = 0; j < nm; ++j) sc.m_I[j] = Rt * (M[j] - t);
  clock.lap(Phase::Dilation);
  indenter_->sdf->values(sc.m_I, sc.phi_I);
  clock.lap(Phase::Sdf);
  for (int kk = 0; kk < nm; ++kk) {
    const double h = std::max(-sc.phi_I[kk], 0.0);
    if (h == 0) continue;
    const double g = k_.kappa_d * h;
    const double* wx = &dil_x_[static_cast<std::size_t>(kk) * nm];
    const double* wy = &dil_y_[static_cast<std::size_t>(kk) * nm];
    for (int j = 0; j < nm; ++j) disp[j] += Vec2(g * wx[j], g * wy[j]);
  }
}

void HydroShearBatch::step_slot(Slot& slot, const Pose& X_EI, Vec2* disp, FieldOutput* diag, Scratch& sc,
                                PhaseClock& clock) const {
  gather_candidates(X_EI, sc);
  clock.lap(Phase::TransformCull);
  commit_state(slot, X_EI, sc);
  const std::vector<HydroShearPoint>& field_points = k_.g_aug > 0 ? augmented_state(slot, X_EI, sc) : slot.points;
  clock.lap(Phase::State);
  shear_sum(field_points, X_EI, sc);
  clock.lap(Phase::Shear);
  dilation(X_EI, disp, sc, clock);
  clock.lap(Phase::Dilation);

  if (diag) {
    const int nm = markers();
    diag->disp_px.assign(disp, disp + nm);
    diag->marker_in_contact.resize(nm);
    for (int j = 0; j < nm; ++j) diag->marker_in_contact[j] = sc.phi_I[j] < 0 ? 1 : 0;
    diag->p_EP.clear();
    diag->anchor_EP.clear();
    diag->point_state.clear();
    for (std::size_t i = 0; i < field_points.size(); ++i) {
      diag->p_EP.push_back(sc.p_of_field[i]);
      diag->anchor_EP.push_back(sc.p_of_field[i] + field_points[i].u_E);
      diag->point_state.push_back(field_points[i].state);
    }
  }
}

}  // namespace sb
