#pragma once
// HydroShear (Dang, Lee et al. 2026) as the authors' code computes it (docs/models.md), in the tsd/1
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
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "core/models/model.hpp"
#include "core/models/model_common.hpp"
#include "core/models/phase_profile.hpp"

namespace sb {

// `layer`: also the near-field term of the bonded-layer hypothesis (model "hydroshear-layer",
// docs/effects.md "Traction through a bonded layer"): the shear kernel gains a narrow second Gaussian,
//   exp(-lambda_s |r|^2)  ->  exp(-lambda_s |r|^2) + beta_s exp(-lambda_s2 |r|^2),
// beta_s = 0 being the authors' kernel.
// `stick`: the stick-zone hypothesis (models "hydroshear-stick", "hydroshear-layer-stick", docs/effects.md
// "The stick zone"): the shear sum saturates where the contact's weights pile up,
//   M_s(m_j) -> M_s(m_j) / (1 + stick_sat W_j),  W_j = sum_i w_i exp(-lambda_s |m_j - a_i|^2),
// so inside a wide stuck contact the field tends to the weighted mean of its points' state (the stuck
// surface moves with the indenter) instead of growing with their number; stick_sat = 0 is the authors' sum.
// `contact` (model "hydroshear-contact", docs/effects.md "Where the tractions act, and the layer's far
// field"): layer + stick and two more terms.
//   - far field: a third, wide Gaussian in the shear kernel, + beta_s3 exp(-lambda_s3 |r|^2): a layer
//     bonded to a rigid base spreads a tangential load over about its thickness and beyond;
//   - contact-following tractions: every kernel centre moves by `follow` times the contact's weighted
//     mean stuck displacement, a_i = o_i + u_i - follow * sum_k w_k u_k^t / sum_k w_k: the authors
//     centre a point's traction where it entered the gel (follow = 0); with follow = 1 a translating,
//     stuck contact's tractions act where the contact is now, while the pattern relative to the mean
//     (a twist's) keeps the authors' placement;
//   - the far field's anisotropy: its term is beta_s3 exp(-l_s3 |d|^2) (v + aniso_s3 l_s3 d (d . v)), d the
//     in-plane offset from the anchor to the marker, v the point's term: a tangential load moves the layer's
//     surface more along itself than across it (Cerruti's Poisson term; aniso_s3 = 0 is isotropic).
std::vector<ParamSpec> hydroshear_param_specs(bool layer = false, bool stick = false, bool contact = false);

// HydroShear's parameters, typed (core/base/typed_params.hpp): each field is one entry of the table behind
// hydroshear_param_specs, whose names are the JSON keys; a field the variant lacks keeps its value here (off).
struct HydroShearParams {
  double lambda_d = 0, lambda_s = 0, mu = 0, kappa_d = 0, kappa_s = 0, K = 0, E = 0, g_aug = 0;
  double g_dir_x = 0, g_dir_y = 0, g_dir_z = 0;  // the augmentation's direction as given ("g_dir_x", ...)
  double beta_s = 0, lambda_s2 = 0;              // the layer kernel's near-field term (0: the authors' kernel)
  double stick_sat = 0;                          // the stick zone's saturation (1/m; 0: the authors' linear sum)
  double beta_s3 = 0, lambda_s3 = 0;             // the far-field term (0: none)
  double follow = 0;                             // contact-following tractions (0: the authors' anchors)
  double aniso_s3 = 0;                           // the far field's anisotropy along the load (0: isotropic)
  bool single_precision = false;  // "float32": the shear sum's products in float (the contact variant's default)
  bool weight_paper = false;      // "weight": false: w = f_n (code); true: w = -phi_E (paper)
  bool normal_indenter = false;   // "normal": false: split along +z_E (code); true: along -n_I (paper)
  bool flat_pad_fast = true;      // analytic phi_E for a flat pad instead of sensor.gel_sdf
  Vec3 g_dir_E = Vec3::Zero();    // unit direction of the gravity augmentation shift, in E (from g_dir_*)
  static HydroShearParams from(const ParamSet& p);
};

// One tracked point's state as a diagnostic.
struct HydroShearPoint {
  int index;     // into indenter.samples.p_IS
  double phi_E;  // phi_E at the last committed step (< 0: in the gel)
  Vec3 u_E;      // state in metres (anchor = point + u)
  double u_n;    // normal part of u (>= 0)
  PointState state;
};

namespace hydroshear {
struct HydroShearModel;
struct Slot;
}  // namespace hydroshear

// E x S independent (environment, sensor) slots sharing one sensor and one indenter. Each slot keeps
// only the points inside the gel (a sparse list in the batch's point order) and the previous pose, so
// memory is O(contact).
//
// A step is four phases per slot (core/models/hydroshear_step.hpp, docs/architecture.md): the candidate points,
// the state, the shear sum, the marker field.
//
// Speed (docs/performance.md). The indenter points are grouped once into small spatial clusters with a
// bounding sphere in I; for a flat pad (gel z_E <= 0) a cluster whose sphere lies above z_E = 0 cannot
// have a point in the gel (phi_E >= z_E > 0), so it costs one dot product and its points are never
// transformed: their state is zero and stays zero, exactly as the dense loop computes it. The shear
// Gaussians factor per grid axis and use a two-exp recurrence (GaussianAxis); the dilation runs only
// when the indenter's SDF bounds reach the marker plane, and only over the markers inside. Per slot,
// the points are handled as columns (structure of arrays) by the branch-free loops of
// core/models/hydroshear_kernels, which the compiler vectorises across points; the slot keeps only each
// tracked point's position, state u and slip flag (u_n and phi_E are recomputed where needed). Every variant
// sums its Gaussian terms in one pass over shared point operands; the contact variant's in single precision by default.
class HydroShearBatch {
 public:
  HydroShearBatch(std::shared_ptr<const Sensor> sensor, std::shared_ptr<const Indenter> indenter, int slots,
                  const ParamSet& params);
  ~HydroShearBatch();
  HydroShearBatch(HydroShearBatch&&) noexcept;
  HydroShearBatch(const HydroShearBatch& other);  // copies the state; fresh scratch
  int slots() const;
  int markers() const;
  void set_params(const ParamSet& params);
  const ParamSet& params() const { return params_; }
  void reset();
  void reset_slot(int slot);
  // X_EI[slot]; disp_px[slot * markers() + j]; diagnostics empty or one per slot. Slots run in parallel.
  // disp_px empty: the state advances and no field is computed (the shear sum and the dilation, most of a
  // step's cost when the markers are not a grid, are skipped); diagnostics must then be empty too.
  static constexpr bool kFieldOptional = true;
  void step(std::span<const Pose> X_EI, double dt, std::span<Vec2> disp_px, std::span<FieldOutput> diagnostics);
  // The committed tracked points of one slot (for tests and the GUI), in the batch's point order
  // (clusters), not sorted by index.
  std::vector<HydroShearPoint> tracked(int slot) const;
  // Phase timing of later steps into `profile` (nullptr: off). Not owned.
  void set_profile(PhaseProfile* profile) { profile_ = profile; }

 private:
  ParamSet params_;
  std::unique_ptr<hydroshear::HydroShearModel> model_;
  std::vector<hydroshear::Slot> slots_;
  PhaseProfile* profile_ = nullptr;
};

}  // namespace sb
