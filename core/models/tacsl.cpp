#include "core/models/tacsl.hpp"

#include "core/base/typed_params.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <stdexcept>

namespace sb {

namespace {
constexpr double kVelocityFloor = 1e-9;   // TacSL: vt / max(|vt|, 1e-9)
constexpr double kNormalizeFloor = 1e-4;  // HydroShear's normalize_tacsl_shear_obs threshold
constexpr int kTacslSlotGrain = 32;       // slots per parallel task (a slot costs about a microsecond)
}  // namespace

namespace {
ParamFields<TacslParams> tacsl_fields(bool normalized) {
  using T = TacslParams;
  ParamFields<TacslParams> f = {
      {{.name = "kn",
        .unit = "1/m",
        .default_value = 1.0,
        .min = 1e-3,
        .max = 1e6,
        .help = "normal penalty gain: f_n = kn * depth (TacSL: 1, so f_n is metres)",
        .log_scale = true},
       &T::kn},
      {{.name = "kt",
        .unit = "s",
        .default_value = 0.1,
        .min = 1e-4,
        .max = 1e6,
        .help = "viscous tangential gain: |f_t| = kt |v_t| in the static branch (TacSL: 0.1)",
        .log_scale = true},
       &T::kt},
      {{.name = "mu",
        .unit = "",
        .default_value = 2.0,
        .min = 0,
        .max = 10,
        .help = "friction cap |f_t| <= mu f_n (TacSL: 2)"},
       &T::mu},
      {{.name = "include_normal",
        .unit = "",
        .default_value = 1,
        .min = 0,
        .max = 1,
        .help = "1: shear = in-plane part of f_n n + f_t (TacSL code); 0: of f_t only"},
       &T::include_normal},
  };
  if (normalized)
    f.push_back({{.name = "gain_px",
                  .unit = "px",
                  .default_value = 1.0,
                  .min = 1e-3,
                  .max = 1e6,
                  .help = "length of the unit shear vectors in the output",
                  .log_scale = true},
                 &T::gain_px});
  else
    f.push_back({{.name = "gain_px",
                  .unit = "px",
                  .default_value = 1000.0,
                  .min = 1e-3,
                  .max = 1e9,
                  .help = "px per unit shear; 1000 gives ~1 px for a 1 mm press sliding at 10 mm/s",
                  .log_scale = true},
                 &T::gain_px});
  return f;
}

// Both tables name the same fields (only gain_px's default and range differ): either reads a set.
const ParamFields<TacslParams>& tacsl_fields_any() {
  static const ParamFields<TacslParams> fields = tacsl_fields(false);
  return fields;
}
}  // namespace

std::vector<ParamSpec> tacsl_param_specs(bool normalized) { return specs_of(tacsl_fields(normalized)); }

TacslBatch::TacslBatch(bool normalized, std::shared_ptr<const Sensor> sensor, std::shared_ptr<const Indenter> indenter,
                       int slots, const ParamSet& params)
    : normalized_(normalized), sensor_(std::move(sensor)), indenter_(std::move(indenter)), slots_(std::max(slots, 0)) {
  if (!sensor_) throw std::invalid_argument("tacsl: sensor required");
  if (!indenter_ || !indenter_->sdf) throw std::invalid_argument("tacsl: indenter with an SDF required");
  set_params(params);
}

void TacslBatch::set_params(const ParamSet& p) {
  params_ = p;
  k_ = read_params(tacsl_fields_any(), p);
}

void TacslBatch::reset() {
  for (int i = 0; i < slots(); ++i) reset_slot(i);
}

void TacslBatch::reset_slot(int slot) {
  Slot& s = slots_.at(slot);
  s.have_prev = false;
  s.X_prev = Pose::Identity();
}

void TacslBatch::step(std::span<const Pose> X_EI, double dt, std::span<Vec2> disp_px,
                      std::span<FieldOutput> diagnostics) {
  const int n = slots();
  const std::size_t nm = sensor_->p_EM.size();
  const char* id = normalized_ ? "tacsl-normalized" : "tacsl";
  if (static_cast<int>(X_EI.size()) != n || disp_px.size() != n * nm)
    throw std::invalid_argument(std::string(id) + ": step needs one pose and markers() displacements per slot");
  if (!diagnostics.empty() && static_cast<int>(diagnostics.size()) != n)
    throw std::invalid_argument(std::string(id) + ": diagnostics must be empty or one per slot");
  if (!std::isfinite(dt)) throw std::invalid_argument(std::string(id) + ": dt is not finite");
  for (const Pose& X : X_EI) require_finite_pose(X, id);
  auto body = [&](const tbb::blocked_range<int>& r) {
    PhaseClock clock(profile_);
    for (int i = r.begin(); i < r.end(); ++i) {
      Vec2* d = &disp_px[i * nm];
      step_slot(slots_[i], X_EI[i], dt, d, clock);
      if (!diagnostics.empty()) marker_contact_diagnostics(d, slots_[i].phi_I, diagnostics[i]);
    }
  };
  for_each_slot_range(n, kTacslSlotGrain, body);
}

void TacslBatch::step_slot(Slot& slot, const Pose& X_EI, double dt, Vec2* disp, PhaseClock& clock) const {
  const auto& M = sensor_->p_EM;
  const std::size_t nm = M.size();
  slot.p_I.resize(nm);
  slot.grad_I.resize(nm);
  slot.phi_I.resize(nm);
  slot.shear.assign(nm, Vec2::Zero());
  const Mat3 R = X_EI.linear();
  const Vec3 t = X_EI.translation();
  const Mat3 Rt = R.transpose();
  for (std::size_t j = 0; j < nm; ++j) slot.p_I[j] = Rt * (M[j] - t);
  clock.lap(Phase::kTransformCull);
  indenter_->sdf->values_and_gradients(slot.p_I, slot.phi_I, slot.grad_I);
  clock.lap(Phase::kSdf);
  const bool moving = slot.have_prev && dt > 0;
  for (std::size_t j = 0; j < nm; ++j) {
    const double d = std::max(-slot.phi_I[j], 0.0);
    if (d <= 0) continue;
    const Vec3 n_I = slot.grad_I[j].normalized();
    const Vec3 n_E = R * n_I;
    Vec3 f_t = Vec3::Zero();
    if (moving) {
      // Velocity of the indenter's material point at the closest surface point c (backward difference).
      const Vec3 c_I = slot.p_I[j] + d * n_I;
      const Vec3 v_rel = -(X_EI * c_I - slot.X_prev * c_I) / dt;
      const Vec3 v_t = v_rel - n_E * n_E.dot(v_rel);
      const double vn = v_t.norm();
      const double f_n = k_.kn * d;
      f_t = -std::min(k_.kt * vn, k_.mu * f_n) * v_t / std::max(vn, kVelocityFloor);
    }
    const Vec3 F = k_.include_normal ? Vec3(k_.kn * d * n_E + f_t) : f_t;
    slot.shear[j] = F.head<2>();
  }
  clock.lap(Phase::kState);
  for (std::size_t j = 0; j < nm; ++j) {
    const Vec2& s = slot.shear[j];
    if (normalized_)
      disp[j] = s.norm() > kNormalizeFloor ? Vec2(k_.gain_px * s / s.norm()) : Vec2::Zero();
    else
      disp[j] = k_.gain_px * s;
  }
  slot.X_prev = X_EI;
  slot.have_prev = true;
  clock.lap(Phase::kShear);
}

}  // namespace sb
