#pragma once
// HydroShear (Dang, Lee et al. 2026) as the authors' code computes it (BASELINES.md §3.3), in the tsd/1
// elastomer frame E (gel z <= 0, +z out of the gel; the authors' frame is this one mirrored in z).
//
// Each indenter surface point o_i = X_EI * o_i^I carries a state u_i (metres): the displacement from
// the point back to its anchor, where it entered the gel (normal part) and where it stuck (tangential
// part). Per step, with s = phi_E(o_t), s' = phi_E(o_{t-1}):
//   alpha = (relu(-s) - relu(-s')) / (s' - s)       (1 in->in, 0 out->out, the in-gel fraction when crossing)
//   delta = alpha (o_{t-1} - o_t)                   (minus the point's motion inside the gel)
//   u_n = relu(u~_n + delta_n),  u_t = u~_t + delta_t,  |u_t| <= (mu E / K) u_n   (stick / slip)
//   u   = H(-s) (u_n n + u_t)                        (reset when the point leaves the gel)
// The "forces" of the paper are f_n = E u_n, f_t = K u_t (area A = 1). Marker field (px):
//   M_d(m_j) = kappa_d sum_k relu(-phi_I(m_k)) (m_j - m_k) exp(-lambda_d |m_j - m_k|^2)
//   M_s(m_j) = kappa_s sum_i w_i (-f_i^xy) exp(-lambda_s |m_j - (o_i + u_i)|^2)
// with w_i = f_n,i (the authors' code) or -phi_E(o_i) (the paper). See docs/models.md.
#include <memory>
#include <span>
#include <vector>

#include "core/model.hpp"
#include "core/model_common.hpp"

namespace sb {

std::vector<ParamSpec> hydroshear_param_specs();

struct HydroShearParams {
  double lambda_d, lambda_s, mu, kappa_d, kappa_s, K, E, g_aug;
  Vec3 g_dir_E;            // unit direction of the gravity augmentation shift, in E
  bool weight_paper;       // false: w = f_n (code); true: w = -phi_E (paper)
  bool normal_indenter;    // false: split along +z_E (code); true: along -n_I (paper)
  bool flat_pad_fast;      // analytic phi_E for a flat pad instead of sensor.gel_sdf
  static HydroShearParams from(const ParamSet& p);
};

// One tracked point's state as a diagnostic.
struct HydroShearPoint {
  int index;               // into indenter.samples.p_IS
  double phi_E;            // phi_E at the last committed step (< 0: in the gel)
  Vec3 u_E;                // state in metres (anchor = point + u)
  double u_n;              // normal part of u (>= 0)
  PointState state;
};

// E x S independent (environment, sensor) slots sharing one sensor and one indenter. Each slot keeps
// only the points inside the gel (a sorted sparse list) and the previous pose, so memory is O(contact).
class HydroShearBatch {
 public:
  HydroShearBatch(std::shared_ptr<const Sensor> sensor, std::shared_ptr<const Indenter> indenter, int slots,
                  const ParamSet& params);
  ~HydroShearBatch();
  HydroShearBatch(HydroShearBatch&&) noexcept;
  HydroShearBatch(const HydroShearBatch& other);   // copies the state; fresh scratch
  int slots() const { return static_cast<int>(slots_.size()); }
  int markers() const { return static_cast<int>(sensor_->p_EM.size()); }
  void set_params(const ParamSet& params);
  const ParamSet& params() const { return params_; }
  void reset();
  void reset_slot(int slot);
  // X_EI[slot]; disp_px[slot * markers() + j]; diagnostics empty or one per slot. Slots run in parallel.
  void step(std::span<const Pose> X_EI, double dt, std::span<Vec2> disp_px, std::span<FieldOutput> diagnostics);
  // The committed tracked points of one slot (for tests and the GUI).
  const std::vector<HydroShearPoint>& tracked(int slot) const { return slots_[slot].points; }

 private:
  struct Slot {
    std::vector<HydroShearPoint> points;   // sorted by index; exactly the points with phi_E < 0
    Pose X_prev = Pose::Identity();
    bool first = true;
  };
  struct Scratch;
  void step_slot(Slot& slot, const Pose& X_EI, Vec2* disp, FieldOutput* diag, Scratch& scratch) const;
  double phi_E(const Vec3& p) const;
  void phi_E_all(std::span<const Vec3> p, std::span<double> phi) const;
  HydroShearPoint advance(const HydroShearPoint* old, int index, const Vec3& n_hat, double s_prev,
                          const Vec3& p_prev, double s, const Vec3& p) const;

  std::shared_ptr<const Sensor> sensor_;
  std::shared_ptr<const Indenter> indenter_;
  ParamSet params_;
  HydroShearParams k_;
  bool flat_ = false;
  FlatPad pad_;
  MarkerGridLayout grid_;
  Eigen::MatrixXd dilation_w_;             // exp(-lambda_d |m_j - m_k|^2), markers are fixed in E
  std::vector<Slot> slots_;
  struct ScratchPool;
  std::unique_ptr<ScratchPool> pool_;
};

}  // namespace sb
