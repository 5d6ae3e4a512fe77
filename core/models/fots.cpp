#include "core/models/fots.hpp"

#include "core/base/typed_params.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace sb {

namespace {

// GelSight Mini 1/0.0634 mm. A function, not a global: the parameter specs may be built by another file's static
// initialiser before this file's globals are set.
double camera_px_per_metre() { return Camera{}.px_per_metre(); }
constexpr int kFotsSlotGrain = 32;  // slots per parallel task (a slot costs about a microsecond)

// Python's int(): truncation toward zero.
double trunc_px(double v, bool integer) { return integer ? std::trunc(v) : v; }

// R(theta) d with c = cos(theta), s = sin(theta) computed once per slot.
Vec2 rotate(const Vec2& d, double c, double s) { return {c * d.x() - s * d.y(), s * d.x() + c * d.y()}; }

// Rotation vector z of a quaternion as torch's quaternion_to_axis_angle computes it: angle
// 2 atan2(|v|, w) in [0, 2 pi] along v/|v| (no wrapping, so the hemisphere of q matters).
double rotvec_z(const Quat& q) {
  const double vn = q.vec().norm();
  if (vn == 0) return 0;
  return 2 * std::atan2(vn, q.w()) * q.z() / vn;
}

}  // namespace

double twist_about_z(const Mat3& R) {
  const Quat q(R);
  double a = 2 * std::atan2(q.z(), q.w());
  if (a > std::numbers::pi) a -= 2 * std::numbers::pi;
  if (a <= -std::numbers::pi) a += 2 * std::numbers::pi;
  return a;
}

namespace {
const ParamFields<FotsParams>& original_fields() {
  using F = FotsParams;
  static const ParamFields<FotsParams> fields = {
      {{.name = "lambda_d",
        .unit = "px^-2",
        .default_value = 0.00125,
        .min = 1e-7,
        .max = 1,
        .help = "dilation Gaussian rate (FOTS calibration, fots_test.py)",
        .log_scale = true},
       &F::lambda_d},
      {{.name = "lambda_s",
        .unit = "px^-2",
        .default_value = 0.00021,
        .min = 1e-7,
        .max = 1,
        .help = "shear Gaussian rate (FOTS calibration)",
        .log_scale = true},
       &F::lambda_s},
      {{.name = "lambda_t",
        .unit = "px^-2",
        .default_value = 0.00038,
        .min = 1e-7,
        .max = 1,
        .help = "twist Gaussian rate (FOTS calibration)",
        .log_scale = true},
       &F::lambda_t},
      {{.name = "px_per_mm",
        .unit = "px/mm",
        .default_value = camera_px_per_metre() * 1e-3,
        .min = 1,
        .max = 100,
        .help = "image scale; default the GelSight Mini camera 1/0.0634 (FOTS repo: 19.58 for its own sensor)"},
       &F::px_per_mm},
      {{.name = "integer_px",
        .unit = "",
        .default_value = 1,
        .min = 0,
        .max = 1,
        .help = "1: truncate the shear vector and anchor to integer px as FOTS's int() (faithful)"},
       &F::integer_px},
      {{.name = "twist_clip_deg",
        .unit = "deg",
        .default_value = 50,
        .min = 0,
        .max = 180,
        .help = "twist angle clip (FOTS: 50)"},
       &F::twist_clip_deg},
  };
  return fields;
}

const ParamFields<FotsParams>& reimpl_fields() {
  using F = FotsParams;
  static const ParamFields<FotsParams> fields = {
      {{.name = "lambda_d",
        .unit = "m^-1",
        .default_value = 300,
        .min = 1,
        .max = 1e5,
        .help = "dilation rate on non-squared distance (HydroShear fots.yaml)",
        .log_scale = true},
       &F::lambda_d},
      {{.name = "lambda_s",
        .unit = "m^-1",
        .default_value = 203.3439,
        .min = 1,
        .max = 1e5,
        .help = "shear rate on non-squared distance",
        .log_scale = true},
       &F::lambda_s},
      {{.name = "lambda_t",
        .unit = "m^-1",
        .default_value = 326,
        .min = 1,
        .max = 1e5,
        .help = "twist rate on non-squared distance",
        .log_scale = true},
       &F::lambda_t},
      {{.name = "kappa_d",
        .unit = "px/m",
        .default_value = 2.5 * camera_px_per_metre(),
        .min = 1,
        .max = 1e9,
        .help = "dilation scale: 2.5 x camera px/m (authors 2.5 x 1/0.065 mm = 38461.5)",
        .log_scale = true},
       &F::kappa_d},
      {{.name = "kappa_s",
        .unit = "px/m",
        .default_value = camera_px_per_metre(),
        .min = 1,
        .max = 1e9,
        .help = "shear scale: camera px/m (authors 15384.6)",
        .log_scale = true},
       &F::kappa_s},
      {{.name = "kappa_t",
        .unit = "px/m",
        .default_value = camera_px_per_metre(),
        .min = 1,
        .max = 1e9,
        .help = "twist scale: camera px/m (authors 15384.6)",
        .log_scale = true},
       &F::kappa_t},
      {{.name = "anchor_grasp",
        .unit = "",
        .default_value = 1,
        .min = 0,
        .max = 1,
        .help =
            "1: the anchor is the patch centre when the normal approach ends, as the authors set it after the grasp "
            "(faithful); 0: at first contact"},
       &F::anchor_grasp},
  };
  return fields;
}
}  // namespace

std::vector<ParamSpec> fots_param_specs() { return specs_of(original_fields()); }
std::vector<ParamSpec> fots_reimpl_param_specs() { return specs_of(reimpl_fields()); }

FotsBatch::FotsBatch(FotsVariant variant, std::shared_ptr<const Sensor> sensor,
                     std::shared_ptr<const Indenter> indenter, int slots, const ParamSet& params)
    : variant_(variant),
      sensor_(std::move(sensor)),
      indenter_(std::move(indenter)),
      slots_(std::max(slots, 0)),
      scratch_(std::max(slots, 0)) {
  if (!sensor_) throw std::invalid_argument("fots: sensor required");
  if (!indenter_ || !indenter_->sdf) throw std::invalid_argument("fots: indenter with an SDF required");
  set_params(params);
}

void FotsBatch::set_params(const ParamSet& p) {
  params_ = p;
  k_ = read_params(variant_ == FotsVariant::kOriginal ? original_fields() : reimpl_fields(), p);
  const auto& M = sensor_->p_EM;
  const int n = static_cast<int>(M.size());
  std::vector<double> dil_x(static_cast<std::size_t>(n) * n), dil_y(dil_x.size());
  auto set_dil = [&](int j, int k, double w, const Vec2& d) {
    dil_x[static_cast<std::size_t>(k) * n + j] = w * d.x();
    dil_y[static_cast<std::size_t>(k) * n + j] = w * d.y();
  };
  if (variant_ == FotsVariant::kOriginal) {
    twist_clip_rad_ = k_.twist_clip_deg * std::numbers::pi / 180;
    // Markers in image pixels at px_per_mm about the principal point (the camera's own scale by default).
    m_px_.resize(n);
    for (int j = 0; j < n; ++j) m_px_[j] = sensor_->camera.principal_px + M[j].head<2>() * (k_.px_per_mm * 1e3);
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k)
        set_dil(j, k, std::exp(-k_.lambda_d * (m_px_[j] - m_px_[k]).squaredNorm()), m_px_[j] - m_px_[k]);
  } else {
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) set_dil(j, k, std::exp(-k_.lambda_d * (M[j] - M[k]).norm()), (M[j] - M[k]).head<2>());
  }
  dil_x_ = std::make_shared<const std::vector<double>>(std::move(dil_x));
  dil_y_ = std::make_shared<const std::vector<double>>(std::move(dil_y));
}

void FotsBatch::reset() {
  for (int i = 0; i < slots(); ++i) reset_slot(i);
}

void FotsBatch::reset_slot(int slot) { slots_.at(slot) = Slot{}; }

void FotsBatch::step(std::span<const Pose> X_EI, double /*dt*/, std::span<Vec2> disp_px,
                     std::span<FieldOutput> diagnostics) {
  const int n = slots();
  const std::size_t nm = sensor_->p_EM.size();
  const char* id = variant_ == FotsVariant::kOriginal ? "fots" : "fots-reimpl";
  if (static_cast<int>(X_EI.size()) != n || disp_px.size() != n * nm)
    throw std::invalid_argument(std::string(id) + ": step needs one pose and markers() displacements per slot");
  if (!diagnostics.empty() && static_cast<int>(diagnostics.size()) != n)
    throw std::invalid_argument(std::string(id) + ": diagnostics must be empty or one per slot");
  for (const Pose& X : X_EI) require_finite_pose(X, id);
  auto body = [&](const tbb::blocked_range<int>& r) {
    PhaseClock clock(profile_);
    for (int i = r.begin(); i < r.end(); ++i) {
      Vec2* d = &disp_px[i * nm];
      if (variant_ == FotsVariant::kOriginal)
        step_original(slots_[i], X_EI[i], d, scratch_[i], clock);
      else
        step_reimpl(slots_[i], X_EI[i], d, scratch_[i], clock);
      if (!diagnostics.empty()) marker_contact_diagnostics(d, scratch_[i].phi_I, diagnostics[i]);
    }
  };
  for_each_slot_range(n, kFotsSlotGrain, body);
}

void FotsBatch::markers_in_indenter(const Pose& X_EI, Scratch& sc, PhaseClock& clock) const {
  const auto& M = sensor_->p_EM;
  const std::size_t nm = M.size();
  sc.m_I.resize(nm);
  sc.phi_I.resize(nm);
  const Mat3 Rt = X_EI.linear().transpose();
  const Vec3 t = X_EI.translation();
  for (std::size_t j = 0; j < nm; ++j) sc.m_I[j] = Rt * (M[j] - t);
  clock.lap(Phase::kTransformCull);
  indenter_->sdf->values(sc.m_I, sc.phi_I);
  clock.lap(Phase::kSdf);
}

void FotsBatch::add_dilation(const Scratch& sc, double g, Vec2* disp) const {
  const int nm = static_cast<int>(sc.phi_I.size());
  for (int k = 0; k < nm; ++k) {
    if (sc.phi_I[k] >= 0) continue;
    const double gh = g * -sc.phi_I[k];
    const double* wx = &(*dil_x_)[static_cast<std::size_t>(k) * nm];
    const double* wy = &(*dil_y_)[static_cast<std::size_t>(k) * nm];
    for (int j = 0; j < nm; ++j) disp[j] += Vec2(gh * wx[j], gh * wy[j]);
  }
}

void FotsBatch::step_original(Slot& slot, const Pose& X_EI, Vec2* disp, Scratch& sc, PhaseClock& clock) const {
  markers_in_indenter(X_EI, sc, clock);
  const int nm = static_cast<int>(sc.phi_I.size());
  bool any = false;
  for (double v : sc.phi_I) any = any || v < 0;
  for (int j = 0; j < nm; ++j) disp[j] = Vec2::Zero();
  if (!any) {  // contact lost: the trajectory history starts again at the next contact
    slot.in_contact = false;
    clock.lap(Phase::kState);
    return;
  }
  if (!slot.in_contact) {
    slot.in_contact = true;
    slot.X_ref = X_EI;
  }
  clock.lap(Phase::kState);
  // Dilate: x' = x + sum_C h_i (x - c_i) exp(-lambda_d |x - c_i|^2), h_i the marker's depth in mm.
  sc.x_px.assign(m_px_.begin(), m_px_.end());
  Vec2* xd = sc.x_px.data();
  add_dilation(sc, 1e3, xd);
  clock.lap(Phase::kDilation);
  // Shear from the planar translation of the indenter origin since first contact (integer px as FOTS).
  const double px_per_m = k_.px_per_mm * 1e3;
  const Vec3 t0 = slot.X_ref.translation(), t1 = X_EI.translation();
  const Vec2 centre = sensor_->camera.principal_px;
  const Vec2 G(trunc_px(t0.x() * px_per_m + centre.x(), k_.integer_px),
               trunc_px(t0.y() * px_per_m + centre.y(), k_.integer_px));
  const Vec2 s(trunc_px((t1.x() - t0.x()) * px_per_m, k_.integer_px),
               trunc_px((t1.y() - t0.y()) * px_per_m, k_.integer_px));
  // Each kernel's exps in one vectorised batch (exp_in_place, <= 1e-14 relative; exponents below -700
  // are clamped, which changes a weight of < 1e-304 by less than itself). The twist is evaluated at the
  // sheared positions, so its batch follows the shear's.
  sc.args.resize(static_cast<std::size_t>(nm));
  for (int j = 0; j < nm; ++j) sc.args[j] = std::max(-k_.lambda_s * (xd[j] - G).squaredNorm(), -700.0);
  exp_in_place(sc.args.data(), nm);
  for (int j = 0; j < nm; ++j) xd[j] += s * sc.args[j];
  // Twist about G by the in-plane rotation since first contact, clipped, at the sheared positions.
  const double raw = twist_about_z(X_EI.linear() * slot.X_ref.linear().transpose());
  const double theta = std::clamp(raw, -twist_clip_rad_, twist_clip_rad_);
  const double ct = std::cos(theta), st = std::sin(theta);
  for (int j = 0; j < nm; ++j) sc.args[j] = std::max(-k_.lambda_t * (xd[j] - G).squaredNorm(), -700.0);
  exp_in_place(sc.args.data(), nm);
  for (int j = 0; j < nm; ++j) {
    const Vec2 d = xd[j] - G;
    xd[j] += (rotate(d, ct, st) - d) * sc.args[j];
  }
  for (int j = 0; j < nm; ++j) disp[j] = xd[j] - m_px_[j];
  clock.lap(Phase::kShear);
}

namespace {
// True when X differs from X_ref only by a translation along z_E (the gel's normal), within what a pose
// recorded to double precision carries: 1 nm in-plane, 1e-9 rad.
bool only_along_normal(const Pose& X_ref, const Pose& X) {
  constexpr double kInPlaneTol = 1e-9;  // m
  constexpr double kAngleTol = 1e-9;    // rad
  const Vec3 dt = X.translation() - X_ref.translation();
  if (dt.head<2>().norm() > kInPlaneTol) return false;
  const Eigen::AngleAxisd dR(X.linear() * X_ref.linear().transpose());
  return std::abs(dR.angle()) <= kAngleTol;
}
}  // namespace

void FotsBatch::step_reimpl(Slot& slot, const Pose& X_EI, Vec2* disp, Scratch& sc, PhaseClock& clock) const {
  markers_in_indenter(X_EI, sc, clock);
  const auto& M = sensor_->p_EM;
  const int nm = static_cast<int>(M.size());
  int n_in = 0;
  Vec3 c_sum = Vec3::Zero();
  for (int j = 0; j < nm; ++j)
    if (sc.phi_I[j] < 0) {
      ++n_in;
      c_sum += sc.m_I[j];
    }
  for (int j = 0; j < nm; ++j) disp[j] = Vec2::Zero();
  if (n_in == 0) {
    // The authors reset the SE(2) history here and write this contact-free pose as its first entry, so
    // the next contact's shear is measured from this pose (HS fots_sensors.py L121-124, L204).
    slot.in_contact = false;
    slot.have_prev = true;
    slot.X_prev = X_EI;
    clock.lap(Phase::kState);
    return;
  }
  auto se2_of = [&](const Pose& X, Quat* q_io, bool continuity) {
    const Pose X_EC = X * Eigen::Translation3d(slot.c_I);
    Quat q(X_EC.linear());
    if (continuity) {
      if (q.coeffs().dot(q_io->coeffs()) < 0) q.coeffs() *= -1;
    } else if (q.w() < 0) {
      q.coeffs() *= -1;  // first entry: canonical hemisphere w >= 0
    }
    *q_io = q;
    return Vec3(X_EC.translation().x(), X_EC.translation().y(), rotvec_z(q));
  };
  if (!slot.in_contact) {
    // Anchor: the contact-patch centre in I, from first contact; the SE(2) history starts at the last
    // contact-free pose (the authors reset it there).
    slot.in_contact = true;
    slot.grasping = k_.anchor_grasp;
    slot.X_ref = slot.have_prev ? slot.X_prev : X_EI;
    slot.c_I = c_sum / n_in;
    slot.se2_ref = se2_of(slot.X_ref, &slot.q_last, false);
  } else if (slot.grasping) {
    // The normal approach (the authors' grasp) goes on while the pose differs from the reference only along
    // the gel's normal; until then the anchor follows the patch centre, which moves along the normal only, so
    // the reference SE(2) keeps its x, y and theta.
    if (only_along_normal(slot.X_ref, X_EI)) {
      slot.c_I = c_sum / n_in;
      slot.se2_ref = se2_of(slot.X_ref, &slot.q_last, false);
    } else {
      slot.grasping = false;
    }
  }
  const Vec3 se2 = se2_of(X_EI, &slot.q_last, true);
  const Vec2 dxy = se2.head<2>() - slot.se2_ref.head<2>();
  const double dtheta = std::clamp(se2.z() - slot.se2_ref.z(), -std::numbers::pi, std::numbers::pi);
  const Vec2 G = slot.se2_ref.head<2>();
  slot.X_prev = X_EI;
  slot.have_prev = true;
  clock.lap(Phase::kState);
  const double ct = std::cos(dtheta), st = std::sin(dtheta);
  // Both kernels' exps in one vectorised batch (exp_in_place; exponents below -700 are clamped, which
  // changes a weight of < 1e-304 by less than itself).
  sc.args.resize(2 * static_cast<std::size_t>(nm));
  for (std::size_t j = 0; j < static_cast<std::size_t>(nm); ++j) {
    const double r = (M[j].head<2>() - G).norm();
    sc.args[2 * j] = std::max(-k_.lambda_s * r, -700.0);
    sc.args[2 * j + 1] = std::max(-k_.lambda_t * r, -700.0);
  }
  exp_in_place(sc.args.data(), 2 * nm);
  for (std::size_t j = 0; j < static_cast<std::size_t>(nm); ++j) {
    const Vec2 d = M[j].head<2>() - G;
    disp[j] = k_.kappa_s * dxy * sc.args[2 * j] + k_.kappa_t * (rotate(d, ct, st) - d) * sc.args[2 * j + 1];
  }
  clock.lap(Phase::kShear);
  add_dilation(sc, k_.kappa_d, disp);
  clock.lap(Phase::kDilation);
}

}  // namespace sb
