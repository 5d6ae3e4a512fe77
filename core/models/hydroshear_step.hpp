#pragma once
// HydroShear's step as phases (core/models/hydroshear.cpp runs them in this order for every slot):
//   1. gather_candidates  the indenter's points that may be in the gel, in E, with phi_E       (Candidates)
//   2. commit_state       the tracker step: points in the gel advance, the others reset        (FieldPoints)
//      augmented_state    with g_aug > 0: one virtual step toward the shifted points, which
//                         replaces the committed state in the field (the slot keeps the committed one)
//   3. shear_sum          M_s before kappa_s, summed over the field's points                      (ShearSums)
//   4. marker_field       kappa_s M_s + kappa_d M_d: the dilation from markers inside the indenter
// Each phase takes what it reads (the immutable HydroShearModel, the previous phase's result) and returns
// what it writes; the buffers it reuses across steps are its own struct, one per thread. The equations are in
// core/models/hydroshear.hpp. Internal: only the HydroShear files include this header.
#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/models/hydroshear.hpp"
#include "core/models/model_common.hpp"
#include "core/models/phase_profile.hpp"

namespace sb::hydroshear {

// Points as columns (structure of arrays), in the batch's point order: what the vectorised kernels read and write.
struct PointColumns {
  std::vector<int> pos;            // position in the point order (PointTable::perm)
  std::vector<double> ux, uy, uz;  // the state u (metres)
  std::vector<std::uint8_t> slip;
  int size() const { return static_cast<int>(pos.size()); }
  void resize(int n);
  void swap(PointColumns& other) noexcept;
};

// One (environment, sensor) slot's path state.
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

// The indenter's points in the batch's order, built once per indenter and shared by copies: the workbench clones
// each model every 16 steps (a checkpoint for seeks), and copying these made a clone O(indenter) instead of
// O(contact) (docs/reliability.md, the soak's memory).
struct PointTable {
  // The point order: pos -> index into samples.p_IS (perm) and back (pos_of); p_I/n_I in that order.
  std::vector<int> perm, pos_of;
  std::vector<Vec3> p_I, n_I;
  std::vector<double> pIx, pIy, pIz;  // p_I as columns
  std::vector<Cluster> clusters;
  // Groups of consecutive clusters (a subtree of the split) with a sphere holding all their points: one test
  // skips the whole group. begin/end index clusters here.
  std::vector<Cluster> groups;
};
std::shared_ptr<const PointTable> make_point_table(const Indenter& indenter);

// Everything a step reads and no step writes: the sensor, the indenter's point table, the parameters and what
// is derived from them (the cull, the shear Gaussians per grid axis, the dilation kernel). set_params rebuilds it.
struct HydroShearModel {
  std::shared_ptr<const Sensor> sensor;
  std::shared_ptr<const Indenter> indenter;
  std::shared_ptr<const PointTable> table;
  HydroShearParams k;
  MarkerGridLayout grid;
  std::vector<double> marker_x, marker_y, marker_z;  // p_EM as columns (the shear sum off a grid)
  double marker_z_max = 0;                           // highest marker (the dilation needs the indenter below it)
  bool flat = false;                                 // the gel is a flat pad: phi_E analytic
  FlatPad pad;
  double cull_z = 0;  // flat pad: points with z_E >= cull_z are outside the gel
  bool cull = false;
  // Any other gel: its mesh's box grown by a margin; a cluster wholly outside it is not in the gel (the
  // TacTip's dome under an 80 mm flat surface: three quarters of the surface's points).
  Eigen::AlignedBox3d gel_box;
  Eigen::AlignedBox3d gel_mesh_bounds;  // the gel mesh's own box (set_params grows it into gel_box)
  bool box_cull = false;
  GaussianAxis gauss_x, gauss_y;    // shear Gaussians along the grid axes (grid.is_grid)
  GaussianAxis gauss_x2, gauss_y2;  // the layer kernel's near-field term (k.beta_s > 0)
  GaussianAxis gauss_x3, gauss_y3;  // the far-field term (k.beta_s3 > 0)
  // Dilation kernel, k-major: dil_x[k * stride + j] = exp(-lambda_d |m_j - m_k|^2) (m_j - m_k).x (and .y),
  // rows padded with zeros to kernels::dilation_stride(nm); shared by the models of one sensor and lambda_d.
  std::shared_ptr<const std::vector<double>> dil_x, dil_y;
  double dil_lambda = 0;  // the lambda_d they were made with

  int markers() const { return static_cast<int>(sensor->p_EM.size()); }
  // Inline: called for every candidate point when the gel is not a flat pad.
  double phi_E(const Vec3& p) const { return flat ? pad.value(p) : sensor->gel_sdf->value(p); }
  void set_params(const HydroShearParams& params);
};

// Phase 1's result: the points of the clusters that can reach the gel (ranges of the point order) with o_i in E
// and phi_E(o_i) (and at the augmentation's shifted pose), and among them the candidates, phi_E < 0 now or at
// the shifted pose (position, visited index).
struct Candidates {
  std::vector<std::pair<int, int>> ranges;
  std::vector<double> vx, vy, vz, vs, vs_aug;
  std::vector<Vec3> points;  // the visited points as vectors for a general gel's batch distance (phi_columns)
  std::vector<int> cpos, ci;
};
const Candidates& gather_candidates(const HydroShearModel& m, const Pose& X_EI, Candidates& out);

// Inputs of one tracker step, one entry per point (kernels::advance_points), and its u_n output.
struct StepColumns {
  std::vector<double> s_prev, qx, qy, qz, s, px, py, pz, ox, oy, oz, nx, ny, nz;
  std::vector<double> un;
  void resize(int n);
};
// Phase 2's buffers: the committed step's and the augmentation's inputs and outputs (next is swapped into the
// slot), and the merge of the old state.
struct StateBuffers {
  StepColumns commit, augment;
  PointColumns next, aug;
  std::vector<int> old_index;
};
// Phase 2's result, what the field reads: the points' state, the real point o_i of each (anchor = o_i + u_i),
// u_n, phi_E (at the shifted point with the augmentation) and the split normal. Views into the slot and the
// StateBuffers: valid until their next step.
struct FieldPoints {
  const PointColumns* state = nullptr;
  const double *un = nullptr, *phi = nullptr;
  const double *x = nullptr, *y = nullptr, *z = nullptr;
  const double *nx = nullptr, *ny = nullptr, *nz = nullptr;
  int size() const { return state->size(); }
};
FieldPoints commit_state(const HydroShearModel& m, const Candidates& c, const Pose& X_EI, Slot& slot,
                         StateBuffers& buf);
FieldPoints augmented_state(const HydroShearModel& m, const Candidates& c, const Pose& X_EI, const Slot& slot,
                            StateBuffers& buf);

// Phase 3's result: per marker, M_s before kappa_s (x, y) and, for the stick saturation, sum_i w_i G_i (w).
struct ShearSums {
  std::vector<double> x, y, w;
};
// Phase 3's buffers (core/models/hydroshear_shear.cpp).
struct ShearBuffers {
  std::vector<double> wvx, wvy, ww;  // the point operands v = -w f^xy and w alone (the stick saturation's)
  std::vector<std::uint8_t> fast;
  std::vector<double> ex, ey;
  std::vector<double> marker_gauss;  // one point's Gaussian at every marker (markers off a grid)
  // The anchors, the exponents of the axis-split factors, the operands of one chunk of points, the lanes'
  // partial sums and the recurrences' running row.
  std::vector<double> anchor_x, anchor_y, anchor_z, axis_args;
  template <typename T>
  struct Operands {
    std::vector<T> vx, vy, w;  // the point operands in T (double reads wvx, wvy, ww)
    std::vector<T> X, W, S;    // one chunk's operands and the lanes' partial sums
  };
  Operands<float> f32;
  Operands<double> f64;
  template <typename T>
  Operands<T>& operands() {
    if constexpr (std::is_same_v<T, float>)
      return f32;
    else
      return f64;
  }
  std::vector<double> run, sums;
  ShearSums out;
};
const ShearSums& shear_sum(const HydroShearModel& m, const FieldPoints& f, ShearBuffers& buf);

// Phase 4's buffers and, for the diagnostics, phi_I at every marker (+inf where the indenter's bounds are above
// every marker).
struct DilationBuffers {
  std::vector<Vec3> m_I;
  std::vector<double> phi_I;
  std::vector<int> dil_k;                    // markers inside the indenter
  std::vector<double> dil_h;                 // and their depths
  std::vector<double> dil_sum_x, dil_sum_y;  // the dilation's sums before kappa_d
};
// disp[j] = kappa_s M_s(m_j) + kappa_d M_d(m_j), M_d from the markers inside the indenter at X_EI.
void marker_field(const HydroShearModel& m, const Pose& X_EI, const ShearSums& shear, Vec2* disp, DilationBuffers& buf,
                  PhaseClock& clock);

// The buffers of the four phases, one per thread, reused across steps (no allocation once the largest contact
// has been seen).
struct StepBuffers {
  Candidates candidates;
  StateBuffers state;
  ShearBuffers shear;
  DilationBuffers dilation;
};

}  // namespace sb::hydroshear
