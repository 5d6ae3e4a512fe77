#include "core/hydroshear.hpp"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <stdexcept>

namespace sb {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
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

// Per-thread buffers: the transformed points and their phi_E, reused across steps (no allocation
// after the first step of the largest indenter).
struct HydroShearBatch::Scratch {
  std::vector<Vec3> p, p_aug;
  std::vector<double> s, s_aug;
  std::vector<HydroShearPoint> next, out;
  std::vector<Vec3> m_I;
  std::vector<double> phi_I;
  std::vector<double> ex, ey;
  std::vector<Vec2> shear;
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
  set_params(params);
}

HydroShearBatch::~HydroShearBatch() = default;
HydroShearBatch::HydroShearBatch(HydroShearBatch&&) noexcept = default;
HydroShearBatch::HydroShearBatch(const HydroShearBatch& o)
    : sensor_(o.sensor_), indenter_(o.indenter_), params_(o.params_), k_(o.k_), flat_(o.flat_), pad_(o.pad_),
      grid_(o.grid_), dilation_w_(o.dilation_w_), slots_(o.slots_), pool_(std::make_unique<ScratchPool>()) {}

void HydroShearBatch::set_params(const ParamSet& params) {
  k_ = HydroShearParams::from(params);
  params_ = params;
  flat_ = k_.flat_pad_fast && flat_pad_of(*sensor_, &pad_);
  const auto& m = sensor_->p_EM;
  const int n = static_cast<int>(m.size());
  dilation_w_.resize(n, n);
  for (int j = 0; j < n; ++j)
    for (int k = 0; k < n; ++k) dilation_w_(j, k) = std::exp(-k_.lambda_d * (m[j] - m[k]).squaredNorm());
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

double HydroShearBatch::phi_E(const Vec3& p) const { return flat_ ? pad_.value(p) : sensor_->gel_sdf->value(p); }

void HydroShearBatch::phi_E_all(std::span<const Vec3> p, std::span<double> phi) const {
  if (flat_) {
    for (std::size_t i = 0; i < p.size(); ++i) phi[i] = pad_.value(p[i]);
  } else {
    sensor_->gel_sdf->values(p, phi);
  }
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
    for (int i = r.begin(); i < r.end(); ++i)
      step_slot(slots_[i], X_EI[i], &disp_px[i * nm], diagnostics.empty() ? nullptr : &diagnostics[i], scratch);
  };
  if (n == 1) {
    body(tbb::blocked_range<int>(0, 1));
  } else {
    tbb::parallel_for(tbb::blocked_range<int>(0, n, 4), body);
  }
}

void HydroShearBatch::step_slot(Slot& slot, const Pose& X_EI, Vec2* disp, FieldOutput* diag, Scratch& sc) const {
  const auto& P_I = indenter_->samples.p_IS;
  const auto& N_I = indenter_->samples.n_IS;
  const int np = static_cast<int>(P_I.size());
  const Mat3 R = X_EI.linear();
  const Vec3 t = X_EI.translation();
  // Normal of the n/t split, pointing out of the gel: +z_E (code) or minus the indenter's outward
  // normal (paper).
  auto n_hat_of = [&](int i) -> Vec3 { return k_.normal_indenter ? Vec3(-(R * N_I[i])) : Vec3::UnitZ(); };

  // 1. Points in E and their phi_E.
  sc.p.resize(np);
  sc.s.resize(np);
  for (int i = 0; i < np; ++i) sc.p[i] = R * P_I[i] + t;
  phi_E_all(sc.p, sc.s);

  // 2. Commit the tracker step. The authors' first call after a reset sets prev = current, so
  // penetration already present then is lost (BASELINES §3.5).
  if (slot.first) slot.X_prev = X_EI;
  sc.next.clear();
  std::size_t k = 0;
  for (int i = 0; i < np; ++i) {
    const HydroShearPoint* old = nullptr;
    if (k < slot.points.size() && slot.points[k].index == i) old = &slot.points[k++];
    if (sc.s[i] >= 0) continue;  // outside (or on) the gel: H(-s) = 0 resets the state
    const Vec3 p_prev = slot.first ? sc.p[i] : Vec3(slot.X_prev * P_I[i]);
    // A point not tracked last step was outside then; its exact phi_E is needed for alpha.
    const double s_prev = slot.first ? sc.s[i] : old ? old->phi_E : phi_E(p_prev);
    sc.next.push_back(advance(old, i, n_hat_of(i), s_prev, p_prev, sc.s[i], sc.p[i]));
  }
  slot.points.swap(sc.next);
  slot.X_prev = X_EI;
  slot.first = false;

  // 3. The state the field uses: the committed one, or one virtual step toward the shifted pose.
  const std::vector<HydroShearPoint>* field_points = &slot.points;
  if (k_.g_aug > 0) {
    const Vec3 shift = k_.g_aug * k_.g_dir_E;
    sc.p_aug.resize(np);
    sc.s_aug.resize(np);
    for (int i = 0; i < np; ++i) sc.p_aug[i] = sc.p[i] + shift;
    phi_E_all(sc.p_aug, sc.s_aug);
    sc.out.clear();
    std::size_t c = 0;
    for (int i = 0; i < np; ++i) {
      const HydroShearPoint* old = nullptr;
      if (c < slot.points.size() && slot.points[c].index == i) old = &slot.points[c++];
      if (sc.s_aug[i] >= 0) continue;
      sc.out.push_back(advance(old, i, n_hat_of(i), sc.s[i], sc.p[i], sc.s_aug[i], sc.p_aug[i]));
    }
    field_points = &sc.out;
  }

  // 4. Shear: M_s(m_j) = kappa_s sum_i w_i (-f_i^xy) exp(-lambda_s |m_j - a_i|^2), anchor a_i = o_i + u_i at
  // the real (not shifted) point, as the authors' code. The kernel uses the 3-D distance (code).
  const auto& M = sensor_->p_EM;
  const int nm = static_cast<int>(M.size());
  sc.shear.assign(nm, Vec2::Zero());
  const double ls = k_.lambda_s;
  for (const HydroShearPoint& q : *field_points) {
    const Vec3 n_hat = n_hat_of(q.index);
    const Vec3 ut = q.u_E - q.u_n * n_hat;
    const Vec3 f = k_.E * q.u_n * n_hat + k_.K * ut;
    const double w = k_.weight_paper ? -q.phi_E : k_.E * q.u_n;
    const Vec2 v = -w * f.head<2>();
    if (v.x() == 0 && v.y() == 0) continue;
    const Vec3 a = sc.p[q.index] + q.u_E;
    if (grid_.is_grid) {
      sc.ex.resize(grid_.cols);
      sc.ey.resize(grid_.rows);
      for (int c = 0; c < grid_.cols; ++c) sc.ex[c] = std::exp(-ls * (grid_.xs[c] - a.x()) * (grid_.xs[c] - a.x()));
      for (int r = 0; r < grid_.rows; ++r) sc.ey[r] = std::exp(-ls * (grid_.ys[r] - a.y()) * (grid_.ys[r] - a.y()));
      const double ez = std::exp(-ls * (grid_.z0 - a.z()) * (grid_.z0 - a.z()));
      for (int r = 0; r < grid_.rows; ++r) {
        const Vec2 vr = v * (ez * sc.ey[r]);
        Vec2* row = &sc.shear[r * grid_.cols];
        for (int c = 0; c < grid_.cols; ++c) row[c] += vr * sc.ex[c];
      }
    } else {
      for (int j = 0; j < nm; ++j) sc.shear[j] += v * std::exp(-ls * (M[j] - a).squaredNorm());
    }
  }

  // 5. Dilation from markers inside the indenter: h_k = relu(-phi_I(X_IE m_k)).
  sc.m_I.resize(nm);
  sc.phi_I.resize(nm);
  const Mat3 Rt = R.transpose();
  for (int j = 0; j < nm; ++j) sc.m_I[j] = Rt * (M[j] - t);
  indenter_->sdf->values(sc.m_I, sc.phi_I);
  for (int j = 0; j < nm; ++j) disp[j] = k_.kappa_s * sc.shear[j];
  for (int kk = 0; kk < nm; ++kk) {
    const double h = std::max(-sc.phi_I[kk], 0.0);
    if (h == 0) continue;
    for (int j = 0; j < nm; ++j) disp[j] += (k_.kappa_d * h * dilation_w_(j, kk)) * (M[j] - M[kk]).head<2>();
  }

  if (diag) {
    diag->disp_px.assign(disp, disp + nm);
    diag->marker_in_contact.resize(nm);
    for (int j = 0; j < nm; ++j) diag->marker_in_contact[j] = sc.phi_I[j] < 0 ? 1 : 0;
    diag->p_EP.clear();
    diag->anchor_EP.clear();
    diag->point_state.clear();
    for (const HydroShearPoint& q : *field_points) {
      diag->p_EP.push_back(sc.p[q.index]);
      diag->anchor_EP.push_back(sc.p[q.index] + q.u_E);
      diag->point_state.push_back(q.state);
    }
  }
}

}  // namespace sb
