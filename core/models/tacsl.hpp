#pragma once
// TacSL penalty-based tactile shear (Akinola et al. 2024; docs/models.md, "TacSL"), the per-taxel model
// HydroShear compares against. Taxels = the markers p_EM; the sensor is static in E, so the relative
// velocity at a taxel is minus the velocity of the indenter's material point at the contact point c:
//   d = max(-phi_I(p_I), 0),  n = R_EI grad phi_I,  c_I = p_I + d n_I
//   v_rel = -(X_EI(t) c_I - X_EI(t - dt) c_I) / dt,  v_t = v_rel - n (n . v_rel)
//   f_n = k_n d,  f_t = -min(k_t |v_t|, mu f_n) v_t / max(|v_t|, 1e-9)
//   shear = (F_x, F_y) with F = f_n n + f_t (authors' code; option: f_t only)
// `tacsl` outputs gain_px * shear; `tacsl-normalized` outputs gain_px * shear/|shear| where
// |shear| > 1e-4, else 0 (normalize_tacsl_shear_obs in HydroShear).
#include <memory>
#include <span>
#include <vector>

#include "core/models/model.hpp"
#include "core/models/model_common.hpp"
#include "core/models/phase_profile.hpp"

namespace sb {

// TacSL's parameters, typed (core/base/typed_params.hpp): each field one entry of the table behind
// tacsl_param_specs (the names are the JSON keys).
struct TacslParams {
  double kn = 0, kt = 0, mu = 0, gain_px = 0;
  bool include_normal = true;
};

std::vector<ParamSpec> tacsl_param_specs(bool normalized);

class TacslBatch {
 public:
  TacslBatch(bool normalized, std::shared_ptr<const Sensor> sensor, std::shared_ptr<const Indenter> indenter, int slots,
             const ParamSet& params);
  int slots() const { return static_cast<int>(slots_.size()); }
  int markers() const { return static_cast<int>(sensor_->p_EM.size()); }
  bool normalized() const { return normalized_; }
  void set_params(const ParamSet& params);
  const ParamSet& params() const { return params_; }
  void reset();
  void reset_slot(int slot);
  // dt <= 0, or the first step after a reset, gives zero velocity.
  void step(std::span<const Pose> X_EI, double dt, std::span<Vec2> disp_px, std::span<FieldOutput> diagnostics);
  // The raw shear (F_x, F_y) of the last step, before gain and normalisation (for tests).
  const std::vector<Vec2>& last_shear(int slot) const { return slots_[slot].shear; }
  // Phase timing of later steps into `profile` (nullptr: off). Not owned.
  void set_profile(PhaseProfile* profile) { profile_ = profile; }

 private:
  struct Slot {
    bool have_prev = false;
    Pose X_prev = Pose::Identity();
    std::vector<Vec3> p_I, grad_I;
    std::vector<double> phi_I;
    std::vector<Vec2> shear;
  };
  void step_slot(Slot& slot, const Pose& X_EI, double dt, Vec2* disp, PhaseClock& clock) const;

  bool normalized_;
  std::shared_ptr<const Sensor> sensor_;
  std::shared_ptr<const Indenter> indenter_;
  ParamSet params_;
  TacslParams k_;
  std::vector<Slot> slots_;
  PhaseProfile* profile_ = nullptr;
};

}  // namespace sb
