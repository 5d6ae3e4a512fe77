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

struct HydroShearParams {
  double lambda_d, lambda_s, mu, kappa_d, kappa_s, K, E, g_aug;
  double beta_s = 0, lambda_s2 = 0;   // the layer kernel's near-field term (0: the authors' kernel)
  double stick_sat = 0;               // the stick zone's saturation (1/m; 0: the authors' linear sum)
  double beta_s3 = 0, lambda_s3 = 0;  // the far-field term (0: none)
  double follow = 0;                  // contact-following tractions (0: the authors' anchors)
  double aniso_s3 = 0;                // the far field's anisotropy along the load (0: isotropic)
  bool shared_pass = false;           // every term in one pass over shared operands (the contact variant)
  bool single_precision = false;      // that pass in single precision (its parameter "float32")
  Vec3 g_dir_E;                       // unit direction of the gravity augmentation shift, in E
  bool weight_paper;                  // false: w = f_n (code); true: w = -phi_E (paper)
  bool normal_indenter;               // false: split along +z_E (code); true: along -n_I (paper)
  bool flat_pad_fast;                 // analytic phi_E for a flat pad instead of sensor.gel_sdf
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

// E x S independent (environment, sensor) slots sharing one sensor and one indenter. Each slot keeps
// only the points inside the gel (a sparse list in the batch's point order) and the previous pose, so
// memory is O(contact).
//
// Speed (docs/performance.md). The indenter points are grouped once into small spatial clusters with a
// bounding sphere in I; for a flat pad (gel z_E <= 0) a cluster whose sphere lies above z_E = 0 cannot
// have a point in the gel (phi_E >= z_E > 0), so it costs one dot product and its points are never
// transformed: their state is zero and stays zero, exactly as the dense loop computes it. The shear
// Gaussians factor per grid axis and use a two-exp recurrence (GaussianAxis); the dilation runs only
// when the indenter's SDF bounds reach the marker plane, and only over the markers inside. Per slot,
// the points are handled as columns (structure of arrays) by the branch-free loops of
// core/models/hydroshear_kernels, which the compiler vectorises across points; the slot keeps only each
// tracked point's position, state u and slip flag (u_n and phi_E are recomputed where needed). The contact
// variant sums its three terms over shared point operands, in single precision by default (shear_sum_shared).
class HydroShearBatch {
 public:
  HydroShearBatch(std::shared_ptr<const Sensor> sensor, std::shared_ptr<const Indenter> indenter, int slots,
                  const ParamSet& params);
  ~HydroShearBatch();
  HydroShearBatch(HydroShearBatch&&) noexcept;
  HydroShearBatch(const HydroShearBatch& other);  // copies the state; fresh scratch
  int slots() const { return static_cast<int>(slots_.size()); }
  int markers() const { return static_cast<int>(sensor_->p_EM.size()); }
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
  // Points as columns (structure of arrays), in point order: what the vectorised kernels read and write.
  struct PointColumns {
    std::vector<int> pos;            // position in the point order (perm_)
    std::vector<double> ux, uy, uz;  // the state u (metres)
    std::vector<std::uint8_t> slip;
    int size() const { return static_cast<int>(pos.size()); }
    void resize(int n);
    void swap(PointColumns& other) noexcept;
  };
  struct Slot {
    PointColumns points;  // exactly the points with phi_E < 0 at the last step
    Pose X_prev = Pose::Identity();
    bool first = true;
  };
  // Consecutive positions [begin, end) of the point order with a bounding sphere in I.
  struct Cluster {
    int begin, end;
    Vec3 centre_I;
    double radius;
  };
  struct Scratch;
  struct StepColumns;
  void build_clusters();
  void step_slot(Slot& slot, const Pose& X_EI, Vec2* disp, FieldOutput* diag, Scratch& scratch,
                 PhaseClock& clock) const;
  void gather_candidates(const Pose& X_EI, Scratch& sc) const;
  void phi_columns(const double* x, const double* y, const double* z, const Vec3& shift, int n, double* phi) const;
  static void lookup_state(const PointColumns& from, const std::vector<int>& pos, std::vector<int>& index,
                           StepColumns& in);
  void commit_state(Slot& slot, const Pose& X_EI, Scratch& sc) const;
  void augmented_state(const Slot& slot, const Pose& X_EI, Scratch& sc) const;
  void normals(const Mat3& R_EI, const std::vector<int>& pos, StepColumns& in) const;
  // One Gaussian term of the shear kernel: weight * exp(-lambda |m - a|^2), with its grid axes.
  struct ShearTerm {
    double weight, lambda;
    const GaussianAxis *gx, *gy;
    bool with_weights = false;  // also sum w_i exp(...) alone into shear_w (the stick saturation's denominator)
    double aniso = 0;           // + aniso lambda d (d . v): the along-the-load anisotropy (contact's far field)
  };
  void contact_shift(Scratch& sc) const;
  void shear_sum(Scratch& sc) const;
  bool factored(const ShearTerm& term) const;  // the term's Gaussians factor on the marker grid
  void add_shear_term(const ShearTerm& term, Scratch& sc) const;
  void shear_sum_fast(const ShearTerm& term, Scratch& sc, int mp) const;
  template <typename T>
  void shear_sum_shared(std::span<const ShearTerm> terms, Scratch& sc) const;
  template <typename T>
  void add_term_shared(const ShearTerm& term, Scratch& sc, int mp) const;
  static Vec2 aniso_term(const ShearTerm& term, const Vec2& d, double vx, double vy);
  // vx, vy, vw: the point's term already scaled by the term's weight.
  void shear_point_slow(const ShearTerm& term, Scratch& sc, int i, double vx, double vy, double vw) const;
  void dilation(const Pose& X_EI, Vec2* disp, Scratch& sc, PhaseClock& clock) const;
  // Inline: called for every candidate point when the gel is not a flat pad.
  double phi_E(const Vec3& p) const { return flat_ ? pad_.value(p) : sensor_->gel_sdf->value(p); }

  std::shared_ptr<const Sensor> sensor_;
  std::shared_ptr<const Indenter> indenter_;
  ParamSet params_;
  HydroShearParams k_;
  bool flat_ = false;
  FlatPad pad_;
  MarkerGridLayout grid_;
  GaussianAxis gauss_x_, gauss_y_;    // shear Gaussians along the grid axes (grid_.is_grid)
  GaussianAxis gauss_x2_, gauss_y2_;  // the layer kernel's near-field term (k_.beta_s > 0)
  GaussianAxis gauss_x3_, gauss_y3_;  // the far-field term (k_.beta_s3 > 0)
  // Dilation kernel, k-major: dil_x_[k * stride + j] = exp(-lambda_d |m_j - m_k|^2) (m_j - m_k).x (and
  // .y), rows padded with zeros to kernels::dilation_stride(nm).
  std::shared_ptr<const std::vector<double>> dil_x_, dil_y_;  // shared by copies (set_params makes new ones)
  double dil_lambda_ = 0;                                     // the lambda_d they were made with
  double marker_z_max_ = 0;  // highest marker (the dilation needs the indenter below it)
  // The indenter's points in the batch's order, built once and shared by copies: the workbench clones each
  // model every 16 steps (a checkpoint for seeks), and copying these made a clone O(indenter) instead of
  // O(contact) (docs/reliability.md, the soak's memory).
  struct PointTable {
    // The point order: pos -> index into samples.p_IS (perm) and back (pos_of); p_I/n_I in that order.
    std::vector<int> perm, pos_of;
    std::vector<Vec3> p_I, n_I;
    std::vector<double> pIx, pIy, pIz;  // p_I as columns
    std::vector<Cluster> clusters;
    // Groups of kClusterGroup consecutive clusters (a subtree of the split) with a sphere holding all
    // their points: one test skips the whole group. begin/end index clusters here.
    std::vector<Cluster> groups;
  };
  std::shared_ptr<const PointTable> table_;
  double cull_z_ = 0;  // points with z_E >= cull_z_ are outside the gel (flat pad)
  bool cull_ = false;
  // Any other gel: its mesh's box grown by a margin (kGelBoxMargin); a cluster wholly outside it is not in the
  // gel (the TacTip's dome under an 80 mm flat surface: three quarters of the surface's points).
  Eigen::AlignedBox3d gel_box_;
  bool box_cull_ = false;
  std::vector<Slot> slots_;
  struct ScratchPool;
  std::unique_ptr<ScratchPool> pool_;
  PhaseProfile* profile_ = nullptr;
};

}  // namespace sb
