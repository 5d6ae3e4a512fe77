#include "core/models/hydroshear.hpp"

#include "core/models/hydroshear_kernels.hpp"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <numeric>
#include <set>
#include <stdexcept>
#include <type_traits>

namespace sb {

namespace kernels = hydroshear_kernels;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Points per cluster of the cull: small enough that a cluster's sphere hugs the surface (about 1.3 mm
// for 0.75 mm spacing), large enough that the per-cluster test is cheap next to the points it skips.
constexpr int kClusterLeaf = 8;
constexpr int kClusterGroup = 8;  // clusters per group of the two-level cull
// Metres added to the cull bound so rounding of the cluster test can never drop a point whose own
// transform would give z_E < cull_z_.
constexpr double kCullMargin = 1e-9;
// Metres around a gel's mesh box beyond which no point can be in the gel: more than a sampled field's voxel
// (at most 0.25 mm) so a mesh gel's field, positive out there, loses nothing to the cull.
constexpr double kGelBoxMargin = 1e-3;
constexpr double kMinExponent = -700;  // exp_in_place's lower limit
// Tasks of the slot loop: slots per task (a slot costs a few microseconds).
constexpr int kSlotGrain = 16;
const double kDefaultPxPerMetre = Camera{}.px_per_metre();  // 1 / 0.0634 mm = 15772.9 px/m

}  // namespace

std::vector<ParamSpec> hydroshear_param_specs(bool layer, bool stick, bool contact) {
  layer = layer || contact;
  stick = stick || contact;
  std::vector<ParamSpec> specs = {
      {"lambda_d", "m^-2", 20000, 1e2, 1e7, "dilation Gaussian rate on squared distance (authors' RL config)", true},
      {"lambda_s", "m^-2", 10800, 1e2, 1e7, "shear Gaussian rate on squared distance (authors' RL config)", true},
      {"mu", "", 0.5, 0, 5, "friction-cone ratio |f_t| <= mu f_n"},
      {"kappa_d", "px/m", kDefaultPxPerMetre, 1, 1e9,
       "dilation scale; default the GelSight Mini camera 1/0.0634 mm (authors: 1/0.065 mm = 15384.6)", true},
      {"kappa_s", "px/m", kDefaultPxPerMetre, 1, 1e9,
       "shear scale; default the GelSight Mini camera 1/0.0634 mm (authors: 1/0.065 mm = 15384.6)", true},
      {"K", "", 1, 1e-3, 1e6, "tangential stiffness gain (authors K = A = 1: state in metres)", true},
      {"E", "", 1, 1e-3, 1e6, "normal stiffness gain (authors E = A = 1: state in metres)", true},
      {"g_aug", "m", 0, 0, 5e-3,
       "gravity augmentation: virtual uncommitted shift of the indenter (authors' RL: 0.25 mm)"},
      {"g_dir_x", "", -1, -1, 1, "x_E component of the augmentation direction (normalised)"},
      {"g_dir_y", "", 0, -1, 1, "y_E component of the augmentation direction"},
      {"g_dir_z", "", 0, -1, 1, "z_E component of the augmentation direction"},
      {"weight", "", 0, 0, 1,
       "shear weight: 0 = accumulated normal state f_n (authors' code), 1 = depth -phi_E (paper)"},
      {"normal", "", 0, 0, 1, "normal of the n/t split: 0 = elastomer +z (authors' code), 1 = indenter normal (paper)"},
      {"flat_pad_fast", "", 1, 0, 1, "1: exact analytic phi_E for a flat pad; 0: always query sensor.gel_sdf"},
  };
  if (layer) {
    // The shear kernel only: the dilation's kernel acts between markers, a pitch (2 mm) apart at least, where
    // a near-field term narrower than the far one adds nothing (fitted, it went to its bound). Ranges: the near-field
    // width 1/sqrt(2 lambda2) between 0.07 mm (finer than the marker pitch can resolve) and 2.2 mm (half the gel's 4.5
    // mm thickness); beta from no near field to 30x the far one.
    const std::vector<ParamSpec> near = {
        {"beta_s", "", 1, 0, 30, "layer kernel: weight of the shear's near-field Gaussian (0 = authors' kernel)"},
        {"lambda_s2", "m^-2", 1e6, 1e5, 1e8, "layer kernel: rate of the shear's near-field Gaussian", true},
    };
    specs.insert(specs.end(), near.begin(), near.end());
  }
  if (stick)
    specs.push_back({"stick_sat", "1/m", 1000, 0, 1e5,
                     "stick zone: the shear sum over 1 + stick_sat sum_i w_i G_i (0 = the authors' linear sum; "
                     "default of the order fitted on twin_sphere35)"});
  if (contact) {
    // Ranges: the far Gaussian's width 1/sqrt(2 lambda_s3) between 2.2 mm (half the gel's thickness, where
    // the near-field term takes over) and 10 mm (half the pad); follow from none to 1.5 (past a rigid
    // translation, so a bound is not where the data's answer hides).
    const std::vector<ParamSpec> more = {
        {"beta_s3", "", 0.05, 0, 2, "far field: weight of the shear's wide Gaussian (0 = none)"},
        {"lambda_s3", "m^-2", 3e4, 5e3, 1e5, "far field: rate of the shear's wide Gaussian", true},
        {"follow", "", 0.75, 0, 1.5,
         "contact-following tractions: kernels shift by follow x the contact's mean stuck displacement "
         "(0 = the authors' anchors, where each point entered)"},
        {"aniso_s3", "", 3, 0, 10,
         "far field's anisotropy: + aniso_s3 l_s3 d (d . v), a tangential load moves the gel more along itself "
         "than across (Cerruti's Poisson term; 0 = isotropic)"},
        {"float32", "", 1, 0, 1,
         "1: the shear sum in single precision (1.75x HydroShear's time; sums within ~1e-6 of the field); "
         "0: in double (2.1x; fits always run it in double)"},
    };
    specs.insert(specs.end(), more.begin(), more.end());
  }
  // What only the shear sum and the dilation read (step_slot's last two phases); mu, E, K, the
  // augmentation and the normal's choice shape the state.
  static const std::set<std::string> field_only = {"lambda_d", "lambda_s",  "kappa_d",   "kappa_s", "weight",
                                                   "beta_s",   "lambda_s2", "stick_sat", "beta_s3", "lambda_s3",
                                                   "follow",   "aniso_s3",  "float32"};
  for (ParamSpec& s : specs) s.field_only = field_only.count(s.name) > 0;
  return specs;
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
  if (p.index_of("beta_s") >= 0) k.beta_s = p.get("beta_s"), k.lambda_s2 = p.get("lambda_s2");
  if (p.index_of("stick_sat") >= 0) k.stick_sat = p.get("stick_sat");
  if (p.index_of("beta_s3") >= 0) k.beta_s3 = p.get("beta_s3"), k.lambda_s3 = p.get("lambda_s3");
  if (p.index_of("follow") >= 0) k.follow = p.get("follow");
  if (p.index_of("aniso_s3") >= 0) k.aniso_s3 = p.get("aniso_s3"), k.shared_pass = true;
  if (p.index_of("float32") >= 0) k.single_precision = param_flag(p, "float32");
  return k;
}

// Inputs of one tracker step, one entry per point (kernels::advance_points).
struct HydroShearBatch::StepColumns {
  std::vector<double> s_prev, qx, qy, qz, s, px, py, pz, ox, oy, oz, nx, ny, nz;
  std::vector<double> un;  // output: the normal part of the new state
  void resize(int n) {
    for (auto* v : {&s_prev, &qx, &qy, &qz, &s, &px, &py, &pz, &ox, &oy, &oz, &nx, &ny, &nz, &un}) v->resize(n);
  }
  kernels::AdvanceColumns view() const {
    return {s_prev.data(), qx.data(), qy.data(), qz.data(), s.data(),  px.data(), py.data(),
            pz.data(),     ox.data(), oy.data(), oz.data(), nx.data(), ny.data(), nz.data()};
  }
};

// Per-thread buffers, reused across steps (no allocation once the largest contact has been seen).
struct HydroShearBatch::Scratch {
  // Visited: the points of the clusters that can reach the gel, as ranges of the point order, with o_i
  // in E and phi_E(o_i) (and at the augmentation's shifted pose).
  std::vector<std::pair<int, int>> ranges;
  std::vector<double> vx, vy, vz, vs, vs_aug;
  // Candidates: visited points with phi_E < 0 now or at the shifted pose (position, visited index).
  std::vector<int> cpos, ci;
  StepColumns commit, augment;  // the committed step's and the augmentation's inputs
  PointColumns next, aug;       // their outputs (next is swapped into the slot)
  // The field's points: state columns, the real point o_i of each (anchor = o_i + u_i) and the normal.
  const PointColumns* field = nullptr;
  const double *field_un = nullptr, *field_phi = nullptr;
  const double *fx = nullptr, *fy = nullptr, *fz = nullptr, *fnx = nullptr, *fny = nullptr, *fnz = nullptr;
  // Shear sum operands (kernels::shear_operands, shear_matrices).
  std::vector<double> wvx, wvy, ww, args, Xt, Wt, S;  // ww: the weights alone (stick saturation)
  std::vector<std::uint8_t> fast;
  std::vector<int> old_index;  // lookup_state's merge
  std::vector<double> ex, ey;
  std::vector<double> marker_gauss;      // one point's Gaussian at every marker (markers off a grid)
  std::vector<double> shear_x, shear_y;  // per marker
  std::vector<double> shear_w;           // sum_i w_i G_i per marker (the stick saturation)
  // The single-precision path (shear_sum_single): the anchors, the exponents of the axis-split factors,
  // the operands of one chunk of points, the 8-lane partial sums and the recurrences' running row.
  std::vector<double> anchor_x, anchor_y, anchor_z, axis_args;
  template <typename T>
  struct Operands {
    std::vector<T> vx, vy, w;  // the point operands in float (double reads wvx, wvy, ww)
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
  double shift_x = 0, shift_y = 0;  // the contact-following shift of every anchor (contact_shift)
  std::vector<Vec3> m_I;
  std::vector<double> phi_I;
  std::vector<int> dil_k;                    // markers inside the indenter
  std::vector<double> dil_h;                 // and their depths
  std::vector<double> dil_sum_x, dil_sum_y;  // the dilation's sums before kappa_d
};
struct HydroShearBatch::ScratchPool {
  tbb::enumerable_thread_specific<Scratch> local;
};

HydroShearBatch::HydroShearBatch(std::shared_ptr<const Sensor> sensor, std::shared_ptr<const Indenter> indenter,
                                 int slots, const ParamSet& params)
    : sensor_(std::move(sensor)),
      indenter_(std::move(indenter)),
      slots_(std::max(slots, 0)),
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
    : sensor_(o.sensor_),
      indenter_(o.indenter_),
      params_(o.params_),
      k_(o.k_),
      flat_(o.flat_),
      pad_(o.pad_),
      grid_(o.grid_),
      gauss_x_(o.gauss_x_),
      gauss_y_(o.gauss_y_),
      gauss_x2_(o.gauss_x2_),
      gauss_y2_(o.gauss_y2_),
      gauss_x3_(o.gauss_x3_),
      gauss_y3_(o.gauss_y3_),
      dil_x_(o.dil_x_),
      dil_y_(o.dil_y_),
      dil_lambda_(o.dil_lambda_),
      marker_z_max_(o.marker_z_max_),
      table_(o.table_),
      cull_z_(o.cull_z_),
      cull_(o.cull_),
      gel_box_(o.gel_box_),
      box_cull_(o.box_cull_),
      slots_(o.slots_),
      pool_(std::make_unique<ScratchPool>()),
      profile_(nullptr) {}

// Recursive median split along the longest axis of the bounding box until kClusterLeaf points remain:
// spatially compact clusters whatever the sample order.
void HydroShearBatch::build_clusters() {
  auto table = std::make_shared<PointTable>();
  auto& perm_ = table->perm;
  auto& pos_of_ = table->pos_of;
  auto& p_I_ = table->p_I;
  auto& n_I_ = table->n_I;
  auto& pIx_ = table->pIx;
  auto& pIy_ = table->pIy;
  auto& pIz_ = table->pIz;
  auto& clusters_ = table->clusters;
  auto& groups_ = table->groups;
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
  pIx_.clear();
  pIy_.clear();
  pIz_.clear();
  n_I_.resize(n);
  for (int pos = 0; pos < n; ++pos) {
    pos_of_[perm_[pos]] = pos;
    p_I_[pos] = P[perm_[pos]];
    pIx_.push_back(p_I_[pos].x());
    pIy_.push_back(p_I_[pos].y());
    pIz_.push_back(p_I_[pos].z());
    n_I_[pos] = indenter_->samples.n_IS[perm_[pos]];
  }
  table_ = std::move(table);
}

void HydroShearBatch::set_params(const ParamSet& params) {
  k_ = HydroShearParams::from(params);
  params_ = params;
  flat_ = k_.flat_pad_fast && flat_pad_of(*sensor_, &pad_);
  // The flat pad occupies z_E <= 0, so phi_E(p) >= z_E: a point at z_E >= 0 is never in the gel. A general
  // gel SDF (a mesh, a nearest-voxel cache) may be negative above its surface, so it is not culled.
  cull_ = flat_;
  cull_z_ = 0;
  box_cull_ = !flat_ && !sensor_->gel_mesh.empty();
  if (box_cull_) {
    gel_box_ = sensor_->gel_mesh.bounds();
    const Vec3 grow = Vec3::Constant(kGelBoxMargin + k_.g_aug);  // the augmented points are tested too
    gel_box_.extend(gel_box_.min() - grow);
    gel_box_.extend(gel_box_.max() + grow);
  }
  // n^2 exponentials (the TacTip's 327 pins: 107k, a millisecond): a fit sets the parameters of every
  // sample's model at every evaluation, mostly with lambda_d unchanged.
  if (!dil_x_ || dil_lambda_ != k_.lambda_d) {
    const auto& m = sensor_->p_EM;
    const int n = static_cast<int>(m.size());
    const int stride = kernels::dilation_stride(n);
    std::vector<double> dil_x(static_cast<std::size_t>(n) * stride, 0.0), dil_y(dil_x.size(), 0.0);
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j) {
        const double w = std::exp(-k_.lambda_d * (m[j] - m[k]).squaredNorm());
        dil_x[k * stride + j] = w * (m[j] - m[k]).x();
        dil_y[k * stride + j] = w * (m[j] - m[k]).y();
      }
    dil_x_ = std::make_shared<const std::vector<double>>(std::move(dil_x));
    dil_y_ = std::make_shared<const std::vector<double>>(std::move(dil_y));
    dil_lambda_ = k_.lambda_d;
  }
  if (grid_.is_grid) {
    gauss_x_ = GaussianAxis(grid_.xs, k_.lambda_s);
    gauss_y_ = GaussianAxis(grid_.ys, k_.lambda_s);
    if (k_.beta_s > 0) {
      gauss_x2_ = GaussianAxis(grid_.xs, k_.lambda_s2);
      gauss_y2_ = GaussianAxis(grid_.ys, k_.lambda_s2);
    }
    if (k_.beta_s3 > 0) {
      gauss_x3_ = GaussianAxis(grid_.xs, k_.lambda_s3);
      gauss_y3_ = GaussianAxis(grid_.ys, k_.lambda_s3);
    }
  }
}

void HydroShearBatch::reset() {
  for (int i = 0; i < slots(); ++i) reset_slot(i);
}

void HydroShearBatch::reset_slot(int slot) {
  Slot& s = slots_.at(slot);
  s.points.resize(0);
  s.first = true;
  s.X_prev = Pose::Identity();
}

void HydroShearBatch::PointColumns::resize(int n) {
  pos.resize(n);
  for (auto* v : {&ux, &uy, &uz}) v->resize(n);
  slip.resize(n);
}

void HydroShearBatch::PointColumns::swap(PointColumns& o) noexcept {
  pos.swap(o.pos);
  ux.swap(o.ux);
  uy.swap(o.uy);
  uz.swap(o.uz);
  slip.swap(o.slip);
}

std::vector<HydroShearPoint> HydroShearBatch::tracked(int slot) const {
  const PointColumns& c = slots_.at(slot).points;
  std::vector<HydroShearPoint> out(c.size());
  for (int i = 0; i < c.size(); ++i) {
    // phi_E and u_n are not kept (they cost memory traffic every step): recomputed at the committed pose.
    const Pose& X = slots_.at(slot).X_prev;
    const int pos = c.pos[i];
    const Vec3 u(c.ux[i], c.uy[i], c.uz[i]);
    const Vec3 n_hat = k_.normal_indenter ? Vec3(-(X.linear() * table_->n_I[pos])) : Vec3::UnitZ();
    out[i] = {table_->perm[pos], phi_E(X * table_->p_I[pos]), u, std::max(u.dot(n_hat), 0.0),
              c.slip[i] ? PointState::Slip : PointState::Stick};
  }
  return out;
}

void HydroShearBatch::step(std::span<const Pose> X_EI, double /*dt: quasi-static, the path is the state*/,
                           std::span<Vec2> disp_px, std::span<FieldOutput> diagnostics) {
  const int n = slots();
  const std::size_t nm = sensor_->p_EM.size();
  const bool field = !disp_px.empty();
  if (static_cast<int>(X_EI.size()) != n || (field && disp_px.size() != n * nm))
    throw std::invalid_argument("hydroshear: step needs one pose per slot and markers() displacements per slot");
  if (!diagnostics.empty() && (!field || static_cast<int>(diagnostics.size()) != n))
    throw std::invalid_argument("hydroshear: diagnostics must be empty or one per slot (with the field)");
  for (const Pose& X : X_EI) require_finite_pose(X, "hydroshear");
  auto body = [&](const tbb::blocked_range<int>& r) {
    Scratch& scratch = pool_->local.local();
    PhaseClock clock(profile_);
    for (int i = r.begin(); i < r.end(); ++i)
      step_slot(slots_[i], X_EI[i], field ? &disp_px[i * nm] : nullptr, diagnostics.empty() ? nullptr : &diagnostics[i],
                scratch, clock);
  };
  for_each_slot_range(n, kSlotGrain, body);
}

namespace {
// The rotation of X row-major and its translation, as the kernels take them.
struct PoseArrays {
  double r[9], t[3];
  explicit PoseArrays(const Pose& X) {
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) r[3 * i + j] = X.linear()(i, j);
      t[i] = X.translation()[i];
    }
  }
};
}  // namespace

// phi[i] = phi_E(p_i + shift) for columns of points.
void HydroShearBatch::phi_columns(const double* x, const double* y, const double* z, const Vec3& shift, int n,
                                  double* phi) const {
  if (flat_) return kernels::flat_pad_phi(pad_, shift.data(), x, y, z, n, phi);
  for (int i = 0; i < n; ++i) phi[i] = sensor_->gel_sdf->value(Vec3(x[i], y[i], z[i]) + shift);
}

// The points that may be in the gel now (or at the augmented pose), with o_i in E and phi_E(o_i).
void HydroShearBatch::gather_candidates(const Pose& X_EI, Scratch& sc) const {
  const PointTable& table = *table_;
  const Mat3 R = X_EI.linear();
  const Vec3 t = X_EI.translation();
  const bool aug = k_.g_aug > 0;
  const Vec3 shift = k_.g_aug * k_.g_dir_E;
  // z_E of a cluster centre is R.row(2) c + t_z; its points are within radius of it. With the
  // augmentation the shifted points must be tested too, so the lower of the two heights counts.
  const Vec3 r_z = R.row(2).transpose();
  const double z_shift_down = aug ? std::min(shift.z(), 0.0) : 0.0;
  // A sphere (centre c, radius r in I) is entirely above the cull plane, also after the shift.
  auto above = [&](const Cluster& c) {
    if (box_cull_) {
      const Vec3 c_E = R * c.centre_I + t;
      return ((c_E.array() + c.radius) < gel_box_.min().array()).any() ||
             ((c_E.array() - c.radius) > gel_box_.max().array()).any();
    }
    return cull_ && r_z.dot(c.centre_I) + t.z() + z_shift_down - c.radius > cull_z_ + kCullMargin;
  };
  sc.ranges.clear();
  int visited = 0;
  auto keep = [&](const Cluster& c) {
    if (!sc.ranges.empty() && sc.ranges.back().second == c.begin)
      sc.ranges.back().second = c.end;
    else
      sc.ranges.emplace_back(c.begin, c.end);
    visited += c.end - c.begin;
  };
  for (const Cluster& g : table.groups) {
    if (above(g)) continue;
    for (int ci = g.begin; ci < g.end; ++ci)
      if (!above(table.clusters[ci])) keep(table.clusters[ci]);
  }
  for (auto* v : {&sc.vx, &sc.vy, &sc.vz, &sc.vs}) v->resize(visited);
  const PoseArrays X(X_EI);
  int off = 0;
  for (const auto& [b, e] : sc.ranges) {
    kernels::transform_points(X.r, X.t, &table.pIx[b], &table.pIy[b], &table.pIz[b], e - b, &sc.vx[off], &sc.vy[off],
                              &sc.vz[off]);
    off += e - b;
  }
  phi_columns(sc.vx.data(), sc.vy.data(), sc.vz.data(), Vec3::Zero(), visited, sc.vs.data());
  if (aug) {
    sc.vs_aug.resize(visited);
    phi_columns(sc.vx.data(), sc.vy.data(), sc.vz.data(), shift, visited, sc.vs_aug.data());
  }
  // Branch-free compaction of the indices alone (whether a point is in the gel is not predictable):
  // every point is written at entry n and n advances only for a kept one, so one spare entry.
  sc.cpos.resize(visited + 1);
  sc.ci.resize(visited + 1);
  int n = 0, i = 0;
  for (const auto& [b, e] : sc.ranges)
    for (int pos = b; pos < e; ++pos, ++i) {
      sc.cpos[n] = pos;
      sc.ci[n] = i;
      n += static_cast<int>(sc.vs[i] < 0) | static_cast<int>(aug && sc.vs_aug[i] < 0);
    }
  sc.cpos.resize(n);
  sc.ci.resize(n);
}

// Normal of the n/t split for the points at `pos`, pointing out of the gel: +z_E (code) or minus the
// indenter's outward normal (paper).
void HydroShearBatch::normals(const Mat3& R_EI, const std::vector<int>& pos, StepColumns& in) const {
  if (!k_.normal_indenter) return;  // +z: the kernels do not read the columns
  const int n = static_cast<int>(pos.size());
  const std::vector<Vec3>& n_I = table_->n_I;
  for (int j = 0; j < n; ++j) {
    const Vec3 nh = -(R_EI * n_I[pos[j]]);
    in.nx[j] = nh.x();
    in.ny[j] = nh.y();
    in.nz[j] = nh.z();
  }
}

// in.o*[j] = the state u of the point at pos[j] in `from` (sorted by position), or 0 when `from` does
// not hold it (the point was outside the gel). A merge of two sorted lists, then the copies.
void HydroShearBatch::lookup_state(const PointColumns& from, const std::vector<int>& pos, std::vector<int>& index,
                                   StepColumns& in) {
  const int n = static_cast<int>(pos.size()), m = from.size();
  index.resize(n);
  const int* fp = from.pos.data();
  const int* p = pos.data();
  int* ix = index.data();
  for (int j = 0, k = 0; j < n; ++j) {
    while (k < m && fp[k] < p[j]) ++k;
    ix[j] = k < m && fp[k] == p[j] ? k : -1;
  }
  const double *ux = from.ux.data(), *uy = from.uy.data(), *uz = from.uz.data();
  double *ox = in.ox.data(), *oy = in.oy.data(), *oz = in.oz.data();
  for (int j = 0; j < n; ++j) {
    const int i = ix[j];
    ox[j] = i >= 0 ? ux[i] : 0.0;
    oy[j] = i >= 0 ? uy[i] : 0.0;
    oz[j] = i >= 0 ? uz[i] : 0.0;
  }
}

// The tracker step: candidates inside the gel advance from their old state (or from zero when they
// enter); every other point's state is reset to zero, i.e. dropped from the sparse list.
void HydroShearBatch::commit_state(Slot& slot, const Pose& X_EI, Scratch& sc) const {
  // The authors' first call after a reset sets prev = current, so penetration already present then
  // is lost (BASELINES §3.5).
  if (slot.first) slot.X_prev = X_EI;
  const int nc = static_cast<int>(sc.cpos.size());
  const int* ci = sc.ci.data();
  const double* vs = sc.vs.data();
  int n_in = 0;
  for (int c = 0; c < nc; ++c) n_in += vs[ci[c]] < 0;
  StepColumns& in = sc.commit;
  PointColumns& next = sc.next;
  in.resize(n_in + 1);  // + 1: the branch-free compaction writes one entry past the last kept
  next.resize(n_in + 1);
  {
    const double *vx = sc.vx.data(), *vy = sc.vy.data(), *vz = sc.vz.data();
    double *px = in.px.data(), *py = in.py.data(), *pz = in.pz.data(), *s = in.s.data();
    int* pos = next.pos.data();
    for (int c = 0, j = 0; c < nc; ++c) {
      const int i = ci[c];
      pos[j] = sc.cpos[c];
      px[j] = vx[i];
      py[j] = vy[i];
      pz[j] = vz[i];
      s[j] = vs[i];
      j += vs[i] < 0;
    }
  }
  in.resize(n_in);
  next.resize(n_in);
  lookup_state(slot.points, next.pos, sc.old_index, in);
  // Each point's previous position o_{t-1} = X_prev X^-1 o_t (one transform of the columns at hand).
  // On the first step o_{t-1} = o_t exactly (the authors' prev = current), not through a rounded identity.
  if (slot.first) {
    in.qx = in.px;
    in.qy = in.py;
    in.qz = in.pz;
  } else {
    const PoseArrays X_PE(slot.X_prev * X_EI.inverse(Eigen::Isometry));
    kernels::transform_points(X_PE.r, X_PE.t, in.px.data(), in.py.data(), in.pz.data(), n_in, in.qx.data(),
                              in.qy.data(), in.qz.data());
  }
  // phi_E at the previous pose only matters for a point that enters the gel: for one that was in the
  // gel (s_prev < 0) and still is, alpha = (-s + s_prev) / (s_prev - s) = 1 exactly, whatever s_prev,
  // and s_prev = s gives that 1 through the 0/0 rule.
  const int* ix = sc.old_index.data();
  for (int j = 0; j < n_in; ++j) in.s_prev[j] = ix[j] >= 0 ? in.s[j] : phi_E(Vec3(in.qx[j], in.qy[j], in.qz[j]));
  normals(X_EI.linear(), next.pos, in);
  kernels::advance_points(in.view(), !k_.normal_indenter, k_.mu * k_.E / k_.K, n_in, next.ux.data(), next.uy.data(),
                          next.uz.data(), in.un.data(), next.slip.data());
  slot.points.swap(next);
  slot.X_prev = X_EI;
  slot.first = false;
  sc.field = &slot.points;
  sc.field_un = in.un.data(), sc.field_phi = in.s.data();
  sc.fx = in.px.data(), sc.fy = in.py.data(), sc.fz = in.pz.data();
  sc.fnx = in.nx.data(), sc.fny = in.ny.data(), sc.fnz = in.nz.data();
}

// The state the field uses with the augmentation: one virtual, uncommitted step from the committed
// state toward the points shifted by g_aug dir.
void HydroShearBatch::augmented_state(const Slot& slot, const Pose& X_EI, Scratch& sc) const {
  const Vec3 shift = k_.g_aug * k_.g_dir_E;
  const int nc = static_cast<int>(sc.cpos.size());
  int n_aug = 0;
  for (int c = 0; c < nc; ++c) n_aug += sc.vs_aug[sc.ci[c]] < 0;
  StepColumns& in = sc.augment;
  PointColumns& out = sc.aug;
  in.resize(n_aug);
  out.resize(n_aug);
  for (int c = 0, j = 0; c < nc; ++c) {
    const int i = sc.ci[c];
    if (sc.vs_aug[i] >= 0) continue;
    in.qx[j] = sc.vx[i];
    in.qy[j] = sc.vy[i];
    in.qz[j] = sc.vz[i];
    in.s_prev[j] = sc.vs[i];
    in.px[j] = sc.vx[i] + shift.x();
    in.py[j] = sc.vy[i] + shift.y();
    in.pz[j] = sc.vz[i] + shift.z();
    in.s[j] = sc.vs_aug[i];
    out.pos[j] = sc.cpos[c];
    ++j;
  }
  lookup_state(slot.points, out.pos, sc.old_index, in);
  normals(X_EI.linear(), out.pos, in);
  kernels::advance_points(in.view(), !k_.normal_indenter, k_.mu * k_.E / k_.K, n_aug, out.ux.data(), out.uy.data(),
                          out.uz.data(), in.un.data(), out.slip.data());
  sc.field = &out;
  sc.field_un = in.un.data(), sc.field_phi = in.s.data();            // phi_E at the shifted point
  sc.fx = in.qx.data(), sc.fy = in.qy.data(), sc.fz = in.qz.data();  // the real, unshifted points
  sc.fnx = in.nx.data(), sc.fny = in.ny.data(), sc.fnz = in.nz.data();
}

// M_s(m_j) = sum_i w_i (-f_i^xy) exp(-lambda_s |m_j - a_i|^2), anchor a_i = o_i + u_i at the real (not
// shifted) point, as the authors' code; the 3-D distance (code). Unscaled (kappa_s applied on output).
//
// On a uniform marker grid the Gaussian of point i at marker (r, c) is
//   exp(-l |m_rc - a_i|^2) = E_i * X_i[c] * Y_i[r],  E_i = exp(-l (d0x^2 + d0y^2 + dz^2)),
// with X_i, Y_i the per-axis ratio recurrences (GaussianAxis): 3 exps per point, batched through
// exp_in_place. The sum over points is then one small matrix product over the points
//   S_x[r][c] = sum_i (vx_i Y_i[r]) (E_i X_i[c])  (and S_y with vy),
// formed with the points as the long, vectorised dimension (kernels::shear_matrices, add_products_nt).
void HydroShearBatch::shear_sum(Scratch& sc) const {
  const int nm = markers();
  sc.shear_x.assign(nm, 0.0);
  sc.shear_y.assign(nm, 0.0);
  if (sc.field->size() == 0) return;
  const bool stick = k_.stick_sat > 0;
  if (stick) sc.shear_w.assign(nm, 0.0);
  contact_shift(sc);
  const ShearTerm terms[] = {{1.0, k_.lambda_s, &gauss_x_, &gauss_y_, stick},
                             {k_.beta_s, k_.lambda_s2, &gauss_x2_, &gauss_y2_},
                             {k_.beta_s3, k_.lambda_s3, &gauss_x3_, &gauss_y3_, false, k_.aniso_s3}};
  if (k_.shared_pass) {
    if (k_.single_precision)
      shear_sum_shared<float>(terms, sc);
    else
      shear_sum_shared<double>(terms, sc);
  } else {
    for (const ShearTerm& term : terms)
      if (term.weight > 0) add_shear_term(term, sc);
  }
  if (!stick) return;
  // The stick zone: where the contact's weights pile up, the field tends to their weighted mean state
  // instead of growing with their sum (docs/effects.md, "The stick zone").
  for (int j = 0; j < nm; ++j) {
    const double f = 1.0 / (1.0 + k_.stick_sat * sc.shear_w[j]);
    sc.shear_x[j] *= f;
    sc.shear_y[j] *= f;
  }
}

// The contact-following shift of every anchor: -follow times the weighted mean tangential state (the
// state points back to where a point stuck, so the shift points along the contact's motion).
void HydroShearBatch::contact_shift(Scratch& sc) const {
  sc.shift_x = sc.shift_y = 0;
  if (k_.follow == 0) return;
  const PointColumns& F = *sc.field;
  const int n = F.size();
  double sw = 0, sx = 0, sy = 0;
  for (int i = 0; i < n; ++i) {
    const double u_n = sc.field_un[i];
    const double w = k_.weight_paper ? -sc.field_phi[i] : k_.E * u_n;
    // The tangential part: with the paper's normal the state's normal component is u_n along n.
    const double tx = F.ux[i] - (k_.normal_indenter ? u_n * sc.fnx[i] : 0.0);
    const double ty = F.uy[i] - (k_.normal_indenter ? u_n * sc.fny[i] : 0.0);
    sw += w, sx += w * tx, sy += w * ty;
  }
  if (sw <= 0) return;
  sc.shift_x = -k_.follow * sx / sw;
  sc.shift_y = -k_.follow * sy / sw;
}

namespace {
// Exponent budget of the factored form: every partial product stays above e^-kMaxTotalExponent, far
// from underflow (e^-708); a point beyond it uses one exp per axis coordinate instead.
constexpr double kMaxTotalExponent = 650;

// Whether an axis' ratio recurrence stays in double's range: its factor q^k = exp(-2 l h^2 k) must not
// underflow before the last marker (a Gaussian far narrower than the pitch: lambda near 1e8 at 2 mm).
bool recurrence_in_range(const GaussianAxis& g) {
  return g.uniform() && 2 * g.lambda() * g.pitch() * g.pitch() * std::max(g.size() - 2, 0) <= kMaxTotalExponent;
}

kernels::ShearConstants axis_constants(const GaussianAxis& gx, const GaussianAxis& gy, double lambda, double z0) {
  kernels::ShearConstants k{};
  k.lambda_s = lambda, k.z0 = z0;
  k.x0 = gx.front(), k.xn = gx.back(), k.hx = gx.pitch();
  k.y0 = gy.front(), k.yn = gy.back(), k.hy = gy.pitch();
  return k;
}
}  // namespace

bool HydroShearBatch::factored(const ShearTerm& term) const {
  return grid_.is_grid && recurrence_in_range(*term.gx) && recurrence_in_range(*term.gy);
}

// Adds weight * sum_i w_i (-f_i^xy) exp(-lambda |m_j - a_i|^2) to the shear sums, in double (the authors'
// model and its layer and stick variants).
void HydroShearBatch::add_shear_term(const ShearTerm& term, Scratch& sc) const {
  const PointColumns& F = *sc.field;
  const int n = F.size();
  const bool fact = factored(term);
  const int mp = (n + 3) / 4 * 4;  // whole 4-double vectors
  // Padding points (n..mp): zero weight, exponents 0 (finite after exp), not fast.
  for (auto* v : {&sc.wvx, &sc.wvy}) v->resize(mp);
  sc.args.resize(3 * static_cast<std::size_t>(mp));
  sc.fast.resize(mp);
  for (int i = n; i < mp; ++i) {
    sc.wvx[i] = sc.wvy[i] = 0;
    sc.args[i] = sc.args[mp + i] = sc.args[2 * mp + i] = 0;
    sc.fast[i] = 0;
  }
  const kernels::ShearColumns cols{sc.fx,       sc.fy,        sc.fz,  F.ux.data(), F.uy.data(), F.uz.data(),
                                   sc.field_un, sc.field_phi, sc.fnx, sc.fny,      sc.fnz};
  kernels::ShearConstants k = fact ? axis_constants(*term.gx, *term.gy, term.lambda, grid_.z0)
                                   : kernels::ShearConstants{};
  k.E = k_.E, k.K = k_.K, k.lambda_s = term.lambda, k.z0 = grid_.z0;
  k.weight_paper = k_.weight_paper, k.normal_z = !k_.normal_indenter;
  k.max_total_exponent = fact ? kMaxTotalExponent : -kInf;  // -inf: every point takes the slow path
  k.shift_x = sc.shift_x, k.shift_y = sc.shift_y;
  double* lead = sc.args.data();
  kernels::shear_operands(cols, k, n, sc.wvx.data(), sc.wvy.data(), lead, lead + mp, lead + std::ptrdiff_t{2} * mp,
                          sc.fast.data());
  // Local pointers: the loops below then vectorise, and the slow path's calls do not reload them.
  double* wvx = sc.wvx.data();
  double* wvy = sc.wvy.data();
  const std::uint8_t* fast = sc.fast.data();
  if (term.weight != 1.0)
    for (int i = 0; i < n; ++i) wvx[i] *= term.weight, wvy[i] *= term.weight;
  const double* ww = nullptr;
  if (term.with_weights) {  // w_i as shear_operands forms it
    sc.ww.assign(mp, 0.0);
    for (int i = 0; i < n; ++i) sc.ww[i] = term.weight * (k_.weight_paper ? -sc.field_phi[i] : k_.E * sc.field_un[i]);
    ww = sc.ww.data();
  }
  for (int i = 0; i < n; ++i)
    if (!fast[i] && (wvx[i] != 0 || wvy[i] != 0 || (ww != nullptr && ww[i] != 0)))
      shear_point_slow(term, sc, i, wvx[i], wvy[i], ww != nullptr ? ww[i] : 0.0);
  if (fact) shear_sum_fast(term, sc, mp);
}

// The contact variant's shear sum, every Gaussian term in one pass over shared point operands: v = -w f^xy,
// w and the anchor a are formed once (kernels::point_operands); per term, its Gaussian splits by axis into
// factors of at most 1 (kernels::axis_exponents), whose recurrences run in double and are stored as T, and
// the products run per chunk of points small enough to stay in the first-level cache, into lane partial
// sums. T = float (parameter float32 = 1, the default): the sums change by ~1e-6 of themselves against
// double (tests/test_hydroshear_contact.cpp), for half the memory traffic and twice the vector width, the
// precision the authors' GPU code computes in. Fits run it in double (their cost must be smooth far below
// that: core/calibration/fit.cpp).
template <typename T>
void HydroShearBatch::shear_sum_shared(std::span<const ShearTerm> terms, Scratch& sc) const {
  const PointColumns& F = *sc.field;
  const int n = F.size();
  const int mp = (n + 7) / 8 * 8;  // whole 8-float vectors
  for (auto* v : {&sc.wvx, &sc.wvy, &sc.ww, &sc.anchor_x, &sc.anchor_y, &sc.anchor_z}) v->assign(mp, 0.0);
  const kernels::ShearColumns cols{sc.fx,       sc.fy,        sc.fz,  F.ux.data(), F.uy.data(), F.uz.data(),
                                   sc.field_un, sc.field_phi, sc.fnx, sc.fny,      sc.fnz};
  kernels::ShearConstants k{};
  k.E = k_.E, k.K = k_.K, k.weight_paper = k_.weight_paper, k.normal_z = !k_.normal_indenter;
  k.shift_x = sc.shift_x, k.shift_y = sc.shift_y;
  kernels::point_operands(cols, k, n, sc.wvx.data(), sc.wvy.data(), sc.ww.data(), sc.anchor_x.data(),
                          sc.anchor_y.data(), sc.anchor_z.data());
  if constexpr (std::is_same_v<T, float>) {  // in double, the terms read sc.wvx, wvy, ww themselves
    auto& ops = sc.operands<T>();
    for (auto [from, to] : {std::pair{&sc.wvx, &ops.vx}, std::pair{&sc.wvy, &ops.vy}, std::pair{&sc.ww, &ops.w}}) {
      to->resize(mp);
      std::copy(from->begin(), from->end(), to->begin());  // rounded to float
    }
  }
  for (const ShearTerm& term : terms)
    if (term.weight > 0) add_term_shared<T>(term, sc, mp);
}

// One Gaussian term of shear_sum_shared: its slow points one by one, the rest factored per chunk.
template <typename T>
void HydroShearBatch::add_term_shared(const ShearTerm& term, Scratch& sc, int mp) const {
  constexpr int kChunk = 96;  // points per chunk: the operands (at most 55 rows of floats) stay in L1
  const int n = sc.field->size();
  const double* vx = sc.wvx.data();
  const double* vy = sc.wvy.data();
  const double* w = sc.ww.data();
  const double tw = term.weight;
  if (!factored(term)) {
    for (int i = 0; i < n; ++i) shear_point_slow(term, sc, i, tw * vx[i], tw * vy[i], tw * w[i]);
    return;
  }
  sc.axis_args.resize(4 * static_cast<std::size_t>(mp));
  sc.fast.resize(mp);
  double* ex0 = sc.axis_args.data();
  double *rx = ex0 + mp, *ey0 = rx + mp, *ry = ey0 + mp;
  kernels::ShearConstants k = axis_constants(*term.gx, *term.gy, term.lambda, grid_.z0);
  k.max_total_exponent = kMaxTotalExponent;
  const int slow = kernels::axis_exponents(sc.anchor_x.data(), sc.anchor_y.data(), sc.anchor_z.data(), k, mp, ex0, rx,
                                           ey0, ry, sc.fast.data());
  const std::uint8_t* fast = sc.fast.data();
  for (int i = 0; i < n && slow > 0; ++i)
    if (!fast[i] && (vx[i] != 0 || vy[i] != 0 || (term.with_weights && w[i] != 0)))
      shear_point_slow(term, sc, i, tw * vx[i], tw * vy[i], tw * w[i]);
  exp_in_place(sc.axis_args.data(), 4 * mp);
  const int rows = grid_.rows, cols = grid_.cols, nm = rows * cols;
  const int cols_pad = (cols + 2) / 3 * 3;
  const bool aniso = term.aniso != 0;
  // Blocks of W per marker row and of X per column: isotropic [vx; vy; (w)] against X; anisotropic
  // [W1; WB (2); WC] against [XC; XA; XB] (kernels::aniso_operands).
  const int w_blocks = aniso ? 4 : (term.with_weights ? 3 : 2);
  const int x_blocks = aniso ? 3 : 1;
  auto& ops = sc.operands<T>();
  constexpr int kLanes = 32 / sizeof(T);  // the partial sums' lanes per output (add_products_acc)
  ops.X.resize(static_cast<std::size_t>(x_blocks) * cols_pad * kChunk);
  ops.W.resize(static_cast<std::size_t>(w_blocks) * rows * kChunk);
  sc.run.resize(kChunk);
  ops.S.assign(kLanes * static_cast<std::size_t>(w_blocks) * nm, T(0));
  T* S = ops.S.data();
  const double kl = term.aniso * term.lambda;
  const T* vxf;
  const T* vyf;
  const T* wf;
  if constexpr (std::is_same_v<T, float>)
    vxf = ops.vx.data(), vyf = ops.vy.data(), wf = ops.w.data();
  else
    vxf = vx, vyf = vy, wf = w;
  for (int off = 0; off < mp; off += kChunk) {
    const int m = std::min(kChunk, mp - off);  // a multiple of 8, as mp and kChunk are
    T* X = ops.X.data();
    T* W = ops.W.data();
    const std::ptrdiff_t xrows = static_cast<std::ptrdiff_t>(cols_pad) * m;
    const std::ptrdiff_t wrows = static_cast<std::ptrdiff_t>(rows) * m;
    if (aniso) {
      kernels::aniso_operands(ex0 + off, rx + off, ey0 + off, ry + off, vxf + off, vyf + off, fast + off,
                              sc.anchor_x.data() + off, sc.anchor_y.data() + off, grid_.xs.data(), grid_.ys.data(),
                              rows, cols, m, term.gx->q(), term.gy->q(), kl, X, W, sc.run.data());
      kernels::add_products_acc(W, rows, X + xrows, cols, m, S);                                // W1 XA
      kernels::add_products_acc(W + wrows, 2 * rows, X + 2 * xrows, cols, m, S + kLanes * nm);  // WB XB
      kernels::add_products_acc(W + 3 * wrows, rows, X, cols, m, S + kLanes * 3 * nm);          // WC XC
    } else {
      kernels::term_operands(ex0 + off, rx + off, ey0 + off, ry + off, vxf + off, vyf + off,
                             term.with_weights ? wf + off : nullptr, fast + off, rows, cols, m, term.gx->q(),
                             term.gy->q(), X, W, sc.run.data());
      kernels::add_products_acc(W, w_blocks * rows, X, cols, m, S);
    }
  }
  sc.sums.resize(static_cast<std::size_t>(w_blocks) * nm);
  kernels::lane_sums(S, w_blocks * nm, sc.sums.data());
  const double* tot = sc.sums.data();
  double* sx = sc.shear_x.data();
  double* sy = sc.shear_y.data();
  if (aniso) {
    // S_x = W1 XA + kl WB[0] XB,  S_y = WC XC + kl WB[1] XB (see kernels::aniso_operands).
    for (int j = 0; j < nm; ++j) {
      sx[j] += tw * (tot[j] + kl * tot[nm + j]);
      sy[j] += tw * (tot[3 * nm + j] + kl * tot[2 * nm + j]);
    }
    return;
  }
  for (int j = 0; j < nm; ++j) {
    sx[j] += tw * tot[j];
    sy[j] += tw * tot[nm + j];
  }
  if (term.with_weights)
    for (int j = 0; j < nm; ++j) sc.shear_w[j] += tw * tot[2 * nm + j];
}

// The fast points' share of the shear sum (see shear_sum).
void HydroShearBatch::shear_sum_fast(const ShearTerm& term, Scratch& sc, int mp) const {
  const int rows = grid_.rows, cols = grid_.cols;
  exp_in_place(sc.args.data(), 3 * mp);
  const int blocks = term.with_weights ? 3 : 2;
  const int cols_pad = (cols + 2) / 3 * 3, nw = blocks * rows, nw_pad = (nw + 2) / 3 * 3;
  sc.Xt.resize(static_cast<std::size_t>(cols_pad) * mp);
  sc.Wt.resize(static_cast<std::size_t>(nw_pad) * mp);
  sc.S.assign(static_cast<std::size_t>(nw) * cols, 0.0);
  const double* e = sc.args.data();
  kernels::shear_matrices(e, e + mp, e + std::ptrdiff_t{2} * mp, sc.wvx.data(), sc.wvy.data(), sc.fast.data(), mp, rows,
                          cols, term.gx->q(), term.gy->q(), sc.Xt.data(), sc.Wt.data(),
                          term.with_weights ? sc.ww.data() : nullptr);
  kernels::add_products_nt(sc.Wt.data(), nw, sc.Xt.data(), cols, mp, sc.S.data());
  const int nm = rows * cols;
  for (int j = 0; j < nm; ++j) {
    sc.shear_x[j] += sc.S[j];
    sc.shear_y[j] += sc.S[nm + j];
  }
  if (term.with_weights)
    for (int j = 0; j < nm; ++j) sc.shear_w[j] += sc.S[2 * nm + j];
}

// A point's term v at in-plane offset d (anchor to marker), with the term's anisotropy: v + k l d (d . v).
Vec2 HydroShearBatch::aniso_term(const ShearTerm& term, const Vec2& d, double vx, double vy) {
  const Vec2 v(vx, vy);
  return term.aniso == 0 ? v : Vec2(v + term.aniso * term.lambda * d * d.dot(v));
}

// One field point's share of the shear sum with one exp per axis coordinate (or per marker off a
// grid): for anchors too far for the factored form, and for marker layouts that are not a uniform grid.
void HydroShearBatch::shear_point_slow(const ShearTerm& term, Scratch& sc, int i, double vx, double vy,
                                       double vw) const {
  const PointColumns& F = *sc.field;
  const Vec3 a(sc.fx[i] + F.ux[i] + sc.shift_x, sc.fy[i] + F.uy[i] + sc.shift_y, sc.fz[i] + F.uz[i]);
  const double ls = term.lambda;
  double* sx = sc.shear_x.data();
  double* sy = sc.shear_y.data();
  double* sw = term.with_weights ? sc.shear_w.data() : nullptr;
  if (grid_.is_grid) {
    const int rows = grid_.rows, cols = grid_.cols;
    sc.ex.resize(cols);
    sc.ey.resize(rows);
    term.gx->eval(a.x(), sc.ex.data());
    term.gy->eval(a.y(), sc.ey.data());
    const double ez = std::exp(-ls * (grid_.z0 - a.z()) * (grid_.z0 - a.z()));
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c) {
        const double g = ez * sc.ey[r] * sc.ex[c];
        const Vec2 v = aniso_term(term, Vec2(grid_.xs[c] - a.x(), grid_.ys[r] - a.y()), vx, vy);
        sx[r * cols + c] += v.x() * g;
        sy[r * cols + c] += v.y() * g;
        if (sw != nullptr) sw[r * cols + c] += vw * g;
      }
    return;
  }
  // Exponents first, then one vectorised exp over them (a point's 327 TacTip pins: this was a third of a scored
  // frame's time in libm's scalar exp). Below kMinExponent the Gaussian is < 1e-304 of its peak: nothing.
  const auto& M = sensor_->p_EM;
  const int nm = static_cast<int>(M.size());
  sc.marker_gauss.resize(nm);
  double* g = sc.marker_gauss.data();
  for (int j = 0; j < nm; ++j) g[j] = std::max(-ls * (M[j] - a).squaredNorm(), kMinExponent);
  exp_in_place(g, nm);
  for (int j = 0; j < nm; ++j) {
    const Vec2 v = aniso_term(term, (M[j] - a).head<2>(), vx, vy);
    sx[j] += v.x() * g[j];
    sy[j] += v.y() * g[j];
    if (sw != nullptr) sw[j] += vw * g[j];
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
  // The markers inside (h > 0), then their kernel rows summed per axis and scaled once.
  sc.dil_k.clear();
  sc.dil_h.clear();
  for (int kk = 0; kk < nm; ++kk) {
    const double h = std::max(-sc.phi_I[kk], 0.0);
    if (h == 0) continue;
    sc.dil_k.push_back(kk);
    sc.dil_h.push_back(h);
  }
  if (sc.dil_k.empty()) return;
  const int stride = kernels::dilation_stride(nm);
  sc.dil_sum_x.resize(stride);
  sc.dil_sum_y.resize(stride);
  kernels::dilation_sum(dil_x_->data(), dil_y_->data(), stride, sc.dil_k.data(), sc.dil_h.data(),
                        static_cast<int>(sc.dil_k.size()), sc.dil_sum_x.data(), sc.dil_sum_y.data());
  const double* dx = sc.dil_sum_x.data();
  const double* dy = sc.dil_sum_y.data();
  for (int j = 0; j < nm; ++j) disp[j] += k_.kappa_d * Vec2(dx[j], dy[j]);
}

void HydroShearBatch::step_slot(Slot& slot, const Pose& X_EI, Vec2* disp, FieldOutput* diag, Scratch& sc,
                                PhaseClock& clock) const {
  gather_candidates(X_EI, sc);
  clock.lap(Phase::TransformCull);
  commit_state(slot, X_EI, sc);
  if (k_.g_aug > 0) augmented_state(slot, X_EI, sc);
  clock.lap(Phase::State);
  if (disp == nullptr) return;  // the state advances; no field is wanted at this step
  shear_sum(sc);
  clock.lap(Phase::Shear);
  dilation(X_EI, disp, sc, clock);
  clock.lap(Phase::Dilation);

  if (diag) {
    const int nm = markers();
    diag->disp_px.assign(disp, disp + nm);
    diag->marker_in_contact.resize(nm);
    for (int j = 0; j < nm; ++j) diag->marker_in_contact[j] = sc.phi_I[j] < 0 ? 1 : 0;
    const PointColumns& F = *sc.field;
    diag->p_EP.resize(F.size());
    diag->anchor_EP.resize(F.size());
    diag->point_state.resize(F.size());
    for (int i = 0; i < F.size(); ++i) {
      diag->p_EP[i] = Vec3(sc.fx[i], sc.fy[i], sc.fz[i]);
      diag->anchor_EP[i] = diag->p_EP[i] + Vec3(F.ux[i], F.uy[i], F.uz[i]);
      diag->point_state[i] = F.slip[i] ? PointState::Slip : PointState::Stick;
    }
  }
}

}  // namespace sb
