#include "core/models/hydroshear.hpp"

#include "core/base/numbers.hpp"
#include "core/base/typed_params.hpp"
#include "core/models/hydroshear_kernels.hpp"
#include "core/models/hydroshear_step.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <numeric>
#include <set>
#include <stdexcept>
#include <type_traits>

namespace sb {

namespace kernels = hydroshear_kernels;
using hydroshear::HydroShearModel;
using hydroshear::Slot;

namespace {

// Points per cluster of the cull: small enough that a cluster's sphere hugs the surface (about 1.3 mm
// for 0.75 mm spacing), large enough that the per-cluster test is cheap next to the points it skips.
constexpr int kClusterLeaf = 8;
constexpr int kClusterGroup = 8;  // clusters per group of the two-level cull
// Metres around a gel's mesh box beyond which no point can be in the gel: more than a sampled field's voxel
// (at most 0.25 mm) so a mesh gel's field, positive out there, loses nothing to the cull.
constexpr double kGelBoxMargin = 1e-3;
// Tasks of the slot loop: slots per task (a slot costs a few microseconds).
constexpr int kHydroShearSlotGrain = 16;
// 1 / 0.0634 mm = 15772.9 px/m. A function, not a global: the parameter specs are built by static initialisers
// elsewhere (a benchmark's registration reads the model registry), which may run before this file's globals.
double default_px_per_metre() { return Camera{}.px_per_metre(); }

}  // namespace

namespace {
// The authors' parameters, in every variant.
ParamFields<HydroShearParams> authors_fields() {
  using P = HydroShearParams;
  return {
      {{.name = "lambda_d",
        .unit = "m^-2",
        .default_value = 20000,
        .min = 1e2,
        .max = 1e7,
        .help = "dilation Gaussian rate on squared distance (authors' RL config)",
        .log_scale = true},
       &P::lambda_d},
      {{.name = "lambda_s",
        .unit = "m^-2",
        .default_value = 10800,
        .min = 1e2,
        .max = 1e7,
        .help = "shear Gaussian rate on squared distance (authors' RL config)",
        .log_scale = true},
       &P::lambda_s},
      {{.name = "mu",
        .unit = "",
        .default_value = 0.5,
        .min = 0,
        .max = 5,
        .help = "friction-cone ratio |f_t| <= mu f_n"},
       &P::mu},
      {{.name = "kappa_d",
        .unit = "px/m",
        .default_value = default_px_per_metre(),
        .min = 1,
        .max = 1e9,
        .help = "dilation scale; default the GelSight Mini camera 1/0.0634 mm (authors: 1/0.065 mm = 15384.6)",
        .log_scale = true},
       &P::kappa_d},
      {{.name = "kappa_s",
        .unit = "px/m",
        .default_value = default_px_per_metre(),
        .min = 1,
        .max = 1e9,
        .help = "shear scale; default the GelSight Mini camera 1/0.0634 mm (authors: 1/0.065 mm = 15384.6)",
        .log_scale = true},
       &P::kappa_s},
      {{.name = "K",
        .unit = "",
        .default_value = 1,
        .min = 1e-3,
        .max = 1e6,
        .help = "tangential stiffness gain (authors K = A = 1: state in metres)",
        .log_scale = true},
       &P::K},
      {{.name = "E",
        .unit = "",
        .default_value = 1,
        .min = 1e-3,
        .max = 1e6,
        .help = "normal stiffness gain (authors E = A = 1: state in metres)",
        .log_scale = true},
       &P::E},
      {{.name = "g_aug",
        .unit = "m",
        .default_value = 0,
        .min = 0,
        .max = 5e-3,
        .help = "gravity augmentation: virtual uncommitted shift of the indenter (authors' RL: 0.25 mm)"},
       &P::g_aug},
      {{.name = "g_dir_x",
        .unit = "",
        .default_value = -1,
        .min = -1,
        .max = 1,
        .help = "x_E component of the augmentation direction (normalised)"},
       &P::g_dir_x},
      {{.name = "g_dir_y",
        .unit = "",
        .default_value = 0,
        .min = -1,
        .max = 1,
        .help = "y_E component of the augmentation direction"},
       &P::g_dir_y},
      {{.name = "g_dir_z",
        .unit = "",
        .default_value = 0,
        .min = -1,
        .max = 1,
        .help = "z_E component of the augmentation direction"},
       &P::g_dir_z},
      {{.name = "weight",
        .unit = "",
        .default_value = 0,
        .min = 0,
        .max = 1,
        .help = "shear weight: 0 = accumulated normal state f_n (authors' code), 1 = depth -phi_E (paper)"},
       &P::weight_paper},
      {{.name = "normal",
        .unit = "",
        .default_value = 0,
        .min = 0,
        .max = 1,
        .help = "normal of the n/t split: 0 = elastomer +z (authors' code), 1 = indenter normal (paper)"},
       &P::normal_indenter},
      {{.name = "flat_pad_fast",
        .unit = "",
        .default_value = 1,
        .min = 0,
        .max = 1,
        .help = "1: exact analytic phi_E for a flat pad; 0: always query sensor.gel_sdf"},
       &P::flat_pad_fast},
  };
}

// The shear kernel only: the dilation's kernel acts between markers, a pitch (2 mm) apart at least, where a
// near-field term narrower than the far one adds nothing (fitted, it went to its bound). Ranges: the near-field
// width 1/sqrt(2 lambda2) between 0.07 mm (finer than the marker pitch can resolve) and 2.2 mm (half the gel's 4.5
// mm thickness); beta from no near field to 30x the far one.
ParamFields<HydroShearParams> layer_fields() {
  using P = HydroShearParams;
  return {
      {{.name = "beta_s",
        .unit = "",
        .default_value = 1,
        .min = 0,
        .max = 30,
        .help = "layer kernel: weight of the shear's near-field Gaussian (0 = authors' kernel)"},
       &P::beta_s},
      {{.name = "lambda_s2",
        .unit = "m^-2",
        .default_value = 1e6,
        .min = 1e5,
        .max = 1e8,
        .help = "layer kernel: rate of the shear's near-field Gaussian",
        .log_scale = true},
       &P::lambda_s2},
  };
}

ParamFields<HydroShearParams> stick_fields() {
  using P = HydroShearParams;
  return {{{.name = "stick_sat",
            .unit = "1/m",
            .default_value = 1000,
            .min = 0,
            .max = 1e5,
            .help = "stick zone: the shear sum over 1 + stick_sat sum_i w_i G_i (0 = the authors' linear sum; "
                    "default of the order fitted on twin_sphere35)"},
           &P::stick_sat}};
}

// Ranges: the far Gaussian's width 1/sqrt(2 lambda_s3) between 2.2 mm (half the gel's thickness, where the
// near-field term takes over) and 10 mm (half the pad); follow from none to 1.5 (past a rigid translation, so a
// bound is not where the data's answer hides).
ParamFields<HydroShearParams> contact_fields() {
  using P = HydroShearParams;
  return {
      {{.name = "beta_s3",
        .unit = "",
        .default_value = 0.05,
        .min = 0,
        .max = 2,
        .help = "far field: weight of the shear's wide Gaussian (0 = none)"},
       &P::beta_s3},
      {{.name = "lambda_s3",
        .unit = "m^-2",
        .default_value = 3e4,
        .min = 5e3,
        .max = 1e5,
        .help = "far field: rate of the shear's wide Gaussian",
        .log_scale = true},
       &P::lambda_s3},
      {{.name = "follow",
        .unit = "",
        .default_value = 0.75,
        .min = 0,
        .max = 1.5,
        .help = "contact-following tractions: kernels shift by follow x the contact's mean stuck displacement "
                "(0 = the authors' anchors, where each point entered)"},
       &P::follow},
      {{.name = "aniso_s3",
        .unit = "",
        .default_value = 3,
        .min = 0,
        .max = 10,
        .help = "far field's anisotropy: + aniso_s3 l_s3 d (d . v), a tangential load moves the gel more along itself "
                "than across (Cerruti's Poisson term; 0 = isotropic)"},
       &P::aniso_s3},
      {{.name = "float32",
        .unit = "",
        .default_value = 1,
        .min = 0,
        .max = 1,
        .help = "1: the shear sum in single precision (1.75x HydroShear's time; sums within ~1e-6 of the field); "
                "0: in double (2.1x; fits always run it in double)"},
       &P::single_precision},
  };
}

ParamFields<HydroShearParams> hydroshear_fields(bool layer, bool stick, bool contact) {
  layer = layer || contact;
  stick = stick || contact;
  ParamFields<HydroShearParams> fields = authors_fields();
  for (auto [on, more] :
       {std::pair{layer, layer_fields()}, std::pair{stick, stick_fields()}, std::pair{contact, contact_fields()}})
    if (on) fields.insert(fields.end(), more.begin(), more.end());
  // What only the shear sum and the dilation read (step_slot's last two phases); mu, E, K, the augmentation and
  // the normal's choice shape the state.
  static const std::set<std::string> field_only = {"lambda_d", "lambda_s",  "kappa_d",   "kappa_s", "weight",
                                                   "beta_s",   "lambda_s2", "stick_sat", "beta_s3", "lambda_s3",
                                                   "follow",   "aniso_s3",  "float32"};
  for (ParamField<HydroShearParams>& f : fields) f.spec.field_only = field_only.count(f.spec.name) > 0;
  return fields;
}
}  // namespace

std::vector<ParamSpec> hydroshear_param_specs(bool layer, bool stick, bool contact) {
  return specs_of(hydroshear_fields(layer, stick, contact));
}

HydroShearParams HydroShearParams::from(const ParamSet& p) {
  static const ParamFields<HydroShearParams> every_variant = hydroshear_fields(true, true, true);
  HydroShearParams k = read_params(every_variant, p);
  const Vec3 dir(k.g_dir_x, k.g_dir_y, k.g_dir_z);
  if (k.g_aug > 0 && dir.norm() == 0)
    throw std::invalid_argument("hydroshear: g_aug > 0 needs a non-zero direction (g_dir_x, g_dir_y, g_dir_z)");
  k.g_dir_E = dir.norm() > 0 ? Vec3(dir.normalized()) : Vec3::Zero();
  return k;
}

namespace {

// One set of step buffers per thread for every batch: the loop's fits hold a model per sample (10,000 on a large
// set), and a set per model and thread was most of their memory. A step never waits on other tasks (step_slot has
// no nested parallelism), so one thread's buffers never serve two steps at once.
hydroshear::StepBuffers& thread_step_buffers() {
  thread_local hydroshear::StepBuffers buffers;
  return buffers;
}

// The point table of `indenter`, built once while some batch over that indenter lives and shared by all of them
// (a fit builds a model per sample, each with the same indenter). Keyed by the indenter's address, checked
// against a weak pointer to it so that a new indenter at a freed one's address gets its own table.
std::shared_ptr<const hydroshear::PointTable> shared_point_table(const std::shared_ptr<const Indenter>& indenter) {
  struct Entry {
    std::weak_ptr<const Indenter> indenter;
    std::weak_ptr<const hydroshear::PointTable> table;
  };
  static std::mutex mutex;
  static std::map<const Indenter*, Entry> tables;
  const std::lock_guard<std::mutex> lock(mutex);
  std::erase_if(tables, [](const auto& e) { return e.second.indenter.expired() || e.second.table.expired(); });
  Entry& e = tables[indenter.get()];
  if (auto table = e.table.lock(); table && e.indenter.lock() == indenter) return table;
  auto table = hydroshear::make_point_table(*indenter);
  e = {indenter, table};
  return table;
}

}  // namespace

HydroShearBatch::HydroShearBatch(std::shared_ptr<const Sensor> sensor, std::shared_ptr<const Indenter> indenter,
                                 int slots, const ParamSet& params)
    : model_(std::make_unique<HydroShearModel>()), slots_(std::max(slots, 0)) {
  if (!sensor || !sensor->gel_sdf) throw std::invalid_argument("hydroshear: sensor with a gel SDF required");
  if (!indenter || !indenter->sdf) throw std::invalid_argument("hydroshear: indenter with an SDF required");
  if (indenter->samples.p_IS.empty()) throw std::invalid_argument("hydroshear: indenter has no surface samples");
  if (indenter->samples.n_IS.size() != indenter->samples.p_IS.size())
    throw std::invalid_argument("hydroshear: indenter samples need one normal per point");
  HydroShearModel& m = *model_;
  m.grid = detect_marker_grid(sensor->p_EM);
  m.marker_z_max = -kInf;
  for (const Vec3& p : sensor->p_EM) {
    m.marker_x.push_back(p.x());
    m.marker_y.push_back(p.y());
    m.marker_z.push_back(p.z());
    m.marker_z_max = std::max(m.marker_z_max, p.z());
  }
  if (!sensor->gel_mesh.empty()) m.gel_mesh_bounds = sensor->gel_mesh.bounds();
  m.table = shared_point_table(indenter);
  m.sensor = std::move(sensor);
  m.indenter = std::move(indenter);
  set_params(params);
}

HydroShearBatch::~HydroShearBatch() = default;
HydroShearBatch::HydroShearBatch(HydroShearBatch&&) noexcept = default;
HydroShearBatch::HydroShearBatch(const HydroShearBatch& o)
    : params_(o.params_), model_(std::make_unique<HydroShearModel>(*o.model_)), slots_(o.slots_), profile_(nullptr) {}

int HydroShearBatch::slots() const { return static_cast<int>(slots_.size()); }
int HydroShearBatch::markers() const { return model_->markers(); }

// Recursive median split along the longest axis of the bounding box until kClusterLeaf points remain:
// spatially compact clusters whatever the sample order.
std::shared_ptr<const hydroshear::PointTable> hydroshear::make_point_table(const Indenter& indenter) {
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
  const auto& P = indenter.samples.p_IS;
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
    n_I_[pos] = indenter.samples.n_IS[perm_[pos]];
  }
  return table;
}

namespace {

// The dilation kernel of a sensor's markers for one lambda_d (HydroShearModel::dil_x, dil_y).
struct DilationKernel {
  std::vector<double> x, y;
};

std::shared_ptr<const DilationKernel> make_dilation_kernel(const std::vector<Vec3>& m, double lambda_d) {
  const int n = static_cast<int>(m.size());
  const int stride = kernels::dilation_stride(n);
  auto d = std::make_shared<DilationKernel>();
  d->x.assign(static_cast<std::size_t>(n) * stride, 0.0);
  d->y.assign(d->x.size(), 0.0);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double w = std::exp(-lambda_d * (m[j] - m[i]).squaredNorm());
      d->x[i * stride + j] = w * (m[j] - m[i]).x();
      d->y[i * stride + j] = w * (m[j] - m[i]).y();
    }
  return d;
}

// n^2 exponentials (the TacTip's 327 pins: 107k) whenever lambda_d changes, and a fit sets the parameters of every
// sample's model (one per sample: 1000 on the TacTip's calibration split) at every run: the samples share the
// last kernel made for a sensor.
std::shared_ptr<const DilationKernel> dilation_kernel(const std::shared_ptr<const Sensor>& sensor, double lambda_d) {
  static std::mutex mutex;
  static std::weak_ptr<const Sensor> last_sensor;
  static double last_lambda = 0;
  static std::shared_ptr<const DilationKernel> last;
  const std::lock_guard<std::mutex> lock(mutex);
  if (last && last_lambda == lambda_d && last_sensor.lock() == sensor) return last;
  last = make_dilation_kernel(sensor->p_EM, lambda_d);
  last_sensor = sensor;
  last_lambda = lambda_d;
  return last;
}

}  // namespace

void hydroshear::HydroShearModel::set_params(const HydroShearParams& params) {
  k = params;
  flat = k.flat_pad_fast && flat_pad_of(*sensor, &pad);
  // The flat pad occupies z_E <= 0, so phi_E(p) >= z_E: a point at z_E >= 0 is never in the gel. A general
  // gel SDF (a mesh, a nearest-voxel cache) may be negative above its surface, so it is not culled.
  cull = flat;
  cull_z = 0;
  box_cull = !flat && !sensor->gel_mesh.empty();
  if (box_cull) {
    gel_box = gel_mesh_bounds;
    const Vec3 grow = Vec3::Constant(kGelBoxMargin + k.g_aug);  // the augmented points are tested too
    gel_box.extend(gel_box.min() - grow);
    gel_box.extend(gel_box.max() + grow);
  }
  if (!dil_x || dil_lambda != k.lambda_d) {
    const std::shared_ptr<const DilationKernel> d = dilation_kernel(sensor, k.lambda_d);
    dil_x = std::shared_ptr<const std::vector<double>>(d, &d->x);
    dil_y = std::shared_ptr<const std::vector<double>>(d, &d->y);
    dil_lambda = k.lambda_d;
  }
  if (grid.is_grid) {
    gauss_x = GaussianAxis(grid.xs, k.lambda_s);
    gauss_y = GaussianAxis(grid.ys, k.lambda_s);
    if (k.beta_s > 0) {
      gauss_x2 = GaussianAxis(grid.xs, k.lambda_s2);
      gauss_y2 = GaussianAxis(grid.ys, k.lambda_s2);
    }
    if (k.beta_s3 > 0) {
      gauss_x3 = GaussianAxis(grid.xs, k.lambda_s3);
      gauss_y3 = GaussianAxis(grid.ys, k.lambda_s3);
    }
  }
}

// Phase 4: kappa_s M_s plus the dilation from markers inside the indenter, h_k = relu(-phi_I(X_IE m_k)).
void hydroshear::marker_field(const HydroShearModel& m, const Pose& X_EI, const ShearSums& shear, Vec2* disp,
                              DilationBuffers& sc, PhaseClock& clock) {
  const auto& M = m.sensor->p_EM;
  const int nm = static_cast<int>(M.size());
  for (int j = 0; j < nm; ++j) disp[j] = m.k.kappa_s * Vec2(shear.x[j], shear.y[j]);
  sc.phi_I.assign(nm, kInf);
  // No marker can be inside the indenter when its SDF bounds (a box in I) lie above every marker.
  const Eigen::AlignedBox3d B = m.indenter->sdf->bounds();
  const Mat3 R = X_EI.linear();
  const Vec3 t = X_EI.translation();
  const Vec3 half = 0.5 * B.sizes();
  const double z_low = (R * B.center() + t).z() - R.row(2).cwiseAbs().dot(half);
  if (z_low > m.marker_z_max) return;
  sc.m_I.resize(nm);
  const Mat3 Rt = R.transpose();
  for (int j = 0; j < nm; ++j) sc.m_I[j] = Rt * (M[j] - t);
  clock.lap(Phase::kDilation);
  m.indenter->sdf->values(sc.m_I, sc.phi_I);
  clock.lap(Phase::kSdf);
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
  kernels::dilation_sum(m.dil_x->data(), m.dil_y->data(), stride, sc.dil_k.data(), sc.dil_h.data(),
                        static_cast<int>(sc.dil_k.size()), sc.dil_sum_x.data(), sc.dil_sum_y.data());
  const double* dx = sc.dil_sum_x.data();
  const double* dy = sc.dil_sum_y.data();
  for (int j = 0; j < nm; ++j) disp[j] += m.k.kappa_d * Vec2(dx[j], dy[j]);
}

void HydroShearBatch::set_params(const ParamSet& params) {
  model_->set_params(HydroShearParams::from(params));
  params_ = params;
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

std::vector<HydroShearPoint> HydroShearBatch::tracked(int slot) const {
  const HydroShearModel& m = *model_;
  const hydroshear::PointColumns& c = slots_.at(slot).points;
  std::vector<HydroShearPoint> out(c.size());
  for (int i = 0; i < c.size(); ++i) {
    // phi_E and u_n are not kept (they cost memory traffic every step): recomputed at the committed pose.
    const Pose& X = slots_.at(slot).X_prev;
    const int pos = c.pos[i];
    const Vec3 u(c.ux[i], c.uy[i], c.uz[i]);
    const Vec3 n_hat = m.k.normal_indenter ? Vec3(-(X.linear() * m.table->n_I[pos])) : Vec3::UnitZ();
    out[i] = {m.table->perm[pos], m.phi_E(X * m.table->p_I[pos]), u, std::max(u.dot(n_hat), 0.0),
              c.slip[i] ? PointState::kSlip : PointState::kStick};
  }
  return out;
}

namespace {

// The field's diagnostics: the marker field, which markers are inside the indenter, and the field's points with
// their anchors and stick/slip states.
void write_diagnostics(const Vec2* disp, int nm, const hydroshear::DilationBuffers& dilation,
                       const hydroshear::FieldPoints& f, FieldOutput& diag) {
  diag.disp_px.assign(disp, disp + nm);
  diag.marker_in_contact.resize(nm);
  for (int j = 0; j < nm; ++j) diag.marker_in_contact[j] = dilation.phi_I[j] < 0 ? 1 : 0;
  const hydroshear::PointColumns& F = *f.state;
  diag.p_EP.resize(F.size());
  diag.anchor_EP.resize(F.size());
  diag.point_state.resize(F.size());
  for (int i = 0; i < F.size(); ++i) {
    diag.p_EP[i] = Vec3(f.x[i], f.y[i], f.z[i]);
    diag.anchor_EP[i] = diag.p_EP[i] + Vec3(F.ux[i], F.uy[i], F.uz[i]);
    diag.point_state[i] = F.slip[i] ? PointState::kSlip : PointState::kStick;
  }
}

// One slot's step: the four phases in order (core/models/hydroshear_step.hpp), each timed.
void step_slot(const HydroShearModel& m, Slot& slot, const Pose& X_EI, Vec2* disp, FieldOutput* diag,
               hydroshear::StepBuffers& sc, PhaseClock& clock) {
  const hydroshear::Candidates& candidates = hydroshear::gather_candidates(m, X_EI, sc.candidates);
  clock.lap(Phase::kTransformCull);
  hydroshear::FieldPoints field = hydroshear::commit_state(m, candidates, X_EI, slot, sc.state);
  if (m.k.g_aug > 0) field = hydroshear::augmented_state(m, candidates, X_EI, slot, sc.state);
  clock.lap(Phase::kState);
  if (disp == nullptr) return;  // the state advances; no field is wanted at this step
  const hydroshear::ShearSums& shear = hydroshear::shear_sum(m, field, sc.shear);
  clock.lap(Phase::kShear);
  hydroshear::marker_field(m, X_EI, shear, disp, sc.dilation, clock);
  clock.lap(Phase::kDilation);
  if (diag) write_diagnostics(disp, m.markers(), sc.dilation, field, *diag);
}

}  // namespace

void HydroShearBatch::step(std::span<const Pose> X_EI, double /*dt: quasi-static, the path is the state*/,
                           std::span<Vec2> disp_px, std::span<FieldOutput> diagnostics) {
  const int n = slots();
  const std::size_t nm = model_->sensor->p_EM.size();
  const bool field = !disp_px.empty();
  if (static_cast<int>(X_EI.size()) != n || (field && disp_px.size() != n * nm))
    throw std::invalid_argument("hydroshear: step needs one pose per slot and markers() displacements per slot");
  if (!diagnostics.empty() && (!field || static_cast<int>(diagnostics.size()) != n))
    throw std::invalid_argument("hydroshear: diagnostics must be empty or one per slot (with the field)");
  for (const Pose& X : X_EI) require_finite_pose(X, "hydroshear");
  const HydroShearModel& m = *model_;
  auto body = [&](const tbb::blocked_range<int>& r) {
    hydroshear::StepBuffers& scratch = thread_step_buffers();
    PhaseClock clock(profile_);
    for (int i = r.begin(); i < r.end(); ++i)
      step_slot(m, slots_[i], X_EI[i], field ? &disp_px[i * nm] : nullptr,
                diagnostics.empty() ? nullptr : &diagnostics[i], scratch, clock);
  };
  for_each_slot_range(n, kHydroShearSlotGrain, body);
}

}  // namespace sb
