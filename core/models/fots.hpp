#pragma once
// FOTS marker motion (Zhao et al. 2024), two variants (docs/models.md, "FOTS, original" and "FOTS Reimpl."):
//
// `fots` — the original repository (Rancho-zhao/FOTS utils/marker_motion.py) lifted from its planar
// trajectory to poses. Image-plane pixels; the trajectory is the in-plane motion of the indenter frame's
// origin (x, y of X_EI) and its in-plane rotation (twist about z_E of R_EI R_EI0^T), since first contact:
//   dilate  x'   = x + sum_{i in C} h_i (x - c_i) exp(-lambda_d |x - c_i|^2)      (h in mm, px, px^-2)
//   shear   x''  = x' + s exp(-lambda_s |x' - G|^2)           s, G integer px (int() truncation)
//   twist   x''' = x'' + (R(theta) d - d) exp(-lambda_t |d|^2),  d = x'' - G,  theta clipped to +-50 deg
//
// `fots-reimpl` — HydroShear's "FOTS (Reimpl.)": metres, non-squared exponential kernels, anchored at
// the initial contact-patch centre c (in I), shear and twist summed at the undeformed markers. The authors
// set c once "after the grasp" (reset_fots in their code); here the grasp is the normal approach: c
// follows the patch centre while the indenter has only moved along the gel's normal since first contact,
// and is fixed from the first step that moves it otherwise (anchor_grasp = 0: fixed at first contact).
//   D_j = kappa_d sum_k h_k (m_j - m_k) exp(-lambda_d |m_j - m_k|)
//   S_j = kappa_s dxy exp(-lambda_s |m_j - G|),  T_j = kappa_t (R(dtheta) d_j - d_j) exp(-lambda_t |d_j|)
#include <memory>
#include <span>
#include <vector>

#include "core/models/model.hpp"
#include "core/models/model_common.hpp"
#include "core/models/phase_profile.hpp"

namespace sb {

enum class FotsVariant { kOriginal, kReimpl };

// FOTS's parameters, typed (core/base/typed_params.hpp): each field one entry of a variant's table (the names
// are the JSON keys); a field the variant lacks keeps its value here.
struct FotsParams {
  double lambda_d = 0, lambda_s = 0, lambda_t = 0;
  double px_per_mm = 0, twist_clip_deg = 0;      // original
  bool integer_px = true;                        // original
  double kappa_d = 0, kappa_s = 0, kappa_t = 0;  // reimpl
  bool anchor_grasp = true;                      // reimpl: the anchor set at the end of the normal approach
};

std::vector<ParamSpec> fots_param_specs();
std::vector<ParamSpec> fots_reimpl_param_specs();

class FotsBatch {
 public:
  FotsBatch(FotsVariant variant, std::shared_ptr<const Sensor> sensor, std::shared_ptr<const Indenter> indenter,
            int slots, const ParamSet& params);
  int slots() const { return static_cast<int>(slots_.size()); }
  int markers() const { return static_cast<int>(sensor_->p_EM.size()); }
  FotsVariant variant() const { return variant_; }
  void set_params(const ParamSet& params);
  const ParamSet& params() const { return params_; }
  void reset();
  void reset_slot(int slot);
  void step(std::span<const Pose> X_EI, double dt, std::span<Vec2> disp_px, std::span<FieldOutput> diagnostics);
  // Phase timing of later steps into `profile` (nullptr: off). Not owned.
  void set_profile(PhaseProfile* profile) { profile_ = profile; }

 private:
  struct Slot {
    bool in_contact = false;        // a history is running
    Pose X_ref = Pose::Identity();  // original: pose at first contact; reimpl: the pose its SE(2) history starts at
    bool grasping = false;          // reimpl: the normal approach is not over (the anchor follows the patch)
    // reimpl: anchor c in I, the reference SE(2) (x, y, theta) and the last quaternion (hemisphere)
    Vec3 c_I = Vec3::Zero();
    Vec3 se2_ref = Vec3::Zero();
    Quat q_last = Quat::Identity();
    bool have_prev = false;  // reimpl: a previous (contact-free) step exists
    Pose X_prev = Pose::Identity();
  };
  struct Scratch {
    std::vector<Vec3> m_I;
    std::vector<double> phi_I;
    std::vector<Vec2> x_px;    // original: the deformed marker positions
    std::vector<double> args;  // reimpl: the shear and twist kernel exponents, then their exps
  };
  void step_original(Slot& slot, const Pose& X_EI, Vec2* disp, Scratch& sc, PhaseClock& clock) const;
  void step_reimpl(Slot& slot, const Pose& X_EI, Vec2* disp, Scratch& sc, PhaseClock& clock) const;
  void markers_in_indenter(const Pose& X_EI, Scratch& sc, PhaseClock& clock) const;
  // disp[j] += sum over markers k inside of g h_k dil_k(j), h_k = relu(-phi_I(m_k)).
  void add_dilation(const Scratch& sc, double g, Vec2* disp) const;

  FotsVariant variant_;
  std::shared_ptr<const Sensor> sensor_;
  std::shared_ptr<const Indenter> indenter_;
  ParamSet params_;
  FotsParams k_;
  double twist_clip_rad_ = 0;  // original
  std::vector<Vec2> m_px_;     // markers in image pixels (original)
  // Constant marker-to-marker dilation kernel, k-major: dil_x_[k * nm + j] = w(j, k) (x_j - x_k) (px
  // for the original, metres for the reimpl.) and the same for y.
  std::shared_ptr<const std::vector<double>> dil_x_, dil_y_;  // shared by copies (set_params makes new ones)
  PhaseProfile* profile_ = nullptr;
  std::vector<Slot> slots_;
  std::vector<Scratch> scratch_;  // one per slot (63 markers: small)
};

// The in-plane rotation angle of R about +z: the twist of its swing-twist decomposition,
// 2 atan2(q_z, q_w) wrapped to (-pi, pi]. Zero for any rotation about an in-plane axis.
double twist_about_z(const Mat3& R);

}  // namespace sb
