// The residual loop (see residual.hpp): base fit, residual structure, effect attribution.
#include "core/loop/residual.hpp"

#include <tbb/parallel_for.h>

#include <Eigen/SVD>
#include <algorithm>
#include <chrono>
#include <functional>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/base/format.hpp"
#include "core/loop/effects.hpp"
#include "core/loop/fingerprints.hpp"
#include "core/data/tsd.hpp"

namespace sb {

namespace {

// Effect parameters a fit must not move: the tracker's moving threshold makes the output discontinuous
// in d (docs/effects.md), so it is held at its default.
bool fixed_effect_param(const std::string& full_name) { return full_name == "tracker_bias.moving_threshold_px"; }

// Depth changes below this (m) count as "held" for the loading covariate (tracking of a held press).
constexpr double kHeldDepthEpsM = 1e-7;

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::unique_ptr<ShearModel> build_model(const std::string& model_id, const std::vector<std::string>& effects,
                                        std::shared_ptr<const Sensor> sensor, std::shared_ptr<const Indenter> ind) {
  auto base = make_model(model_id, sensor, ind);
  if (effects.empty()) return base;
  return wrap_with_effects(std::move(base), effects, sensor, ind);
}

// The parameters of `effect_id` a fit may move: all but the tracker's threshold and those a fingerprint
// fixed (`held`, full names).
std::vector<std::string> effect_free_params(const ParamSet& table, const std::string& effect_id,
                                            const std::vector<std::string>& held = {}) {
  std::vector<std::string> out;
  const std::string prefix = effect_id + kEffectParamSeparator;
  for (const auto& s : table.specs())
    if (s.name.rfind(prefix, 0) == 0 && !fixed_effect_param(s.name) &&
        std::find(held.begin(), held.end(), s.name) == held.end())
      out.push_back(s.name);
  return out;
}

// A fitted parameter closer to a bound than this fraction of its range (log range for log-scale specs)
// sits at the bound.
constexpr double kAtBoundFraction = 0.005;

// The free parameters of `effect_id` that sit at a bound of their range ("name = value"), except a bound
// that is the parameter's own "no effect" default (subsurface depth 0, edge strength 0): reaching that
// means the effect switched itself off, not that it was pushed past physics.
std::string params_at_bound(const ParamSet& params, const std::string& effect_id,
                            const std::vector<std::string>& held) {
  std::string out;
  for (const auto& name : effect_free_params(params, effect_id, held)) {
    const ParamSpec& sp = params.specs()[static_cast<std::size_t>(params.index_of(name))];
    const double v = params.get(name);
    const bool lg = sp.log_scale && sp.min > 0;
    const auto x = [&](double u) { return lg ? std::log(u) : u; };
    const double tol = kAtBoundFraction * (x(sp.max) - x(sp.min));
    for (double b : {sp.min, sp.max}) {
      if (std::abs(x(v) - x(b)) > tol || b == sp.default_value) continue;
      char buf[160];
      std::snprintf(buf, sizeof buf, "%s%s = %.4g", out.empty() ? "" : ", ", name.c_str(), v);
      out += buf;
    }
  }
  return out;
}

// Per-sample squared error and marker-frame count over the scored set, plus the metric accumulators.
struct Scores {
  std::vector<double> sse, count;
  MotionMetrics metrics;
  double held_sse = 0, held_signal = 0, held_count = 0;   // the held-drift fingerprint (FitResult)
};

// Pose changes below these count as "held still" for the held-drift fingerprint.
constexpr double kHeldTranslationM = 1e-9;
constexpr double kHeldRotation = 1e-9;

// The held-drift fingerprint of one sample: over every run of frames in which the indenter is in the gel
// and its pose does not change, the change of the field since the run's first frame, measured against
// predicted, on the markers that moved >= kActiveFramePx when the hold began. Adds sum |dmeas - dpred|^2,
// sum |dmeas|^2 and the count of marker-frames.
void held_drift(const Sensor& sensor, const FitSample& s, const std::vector<std::vector<Vec2>>& pred, Scores* sc,
                std::size_t i, std::vector<double>* sse, std::vector<double>* signal, std::vector<double>* count) {
  (void)sc;
  std::size_t start = 0;
  bool in_run = false;
  for (std::size_t k = 1; k < s.X_EI.size(); ++k) {
    const bool still = (s.X_EI[k].translation() - s.X_EI[k - 1].translation()).norm() < kHeldTranslationM &&
                       (s.X_EI[k].linear() - s.X_EI[k - 1].linear()).norm() < kHeldRotation;
    if (!still) {
      in_run = false;
      continue;
    }
    if (!in_run) {
      if (!indenter_penetration(*sensor.gel_sdf, *s.indenter, s.X_EI[k]).penetrating) continue;
      in_run = true;
      start = k - 1;
    }
    for (std::size_t j = 0; j < s.meas_px[k].size(); ++j) {
      const Vec2 dm = s.meas_px[k][j] - s.meas_px[start][j];
      const Vec2 dp = pred[k][j] - pred[start][j];
      // Only markers the load moves: creep is proportional to the field, the others hold only noise.
      if (!dm.allFinite() || !(s.meas_px[start][j].norm() >= kActiveFramePx)) continue;
      (*sse)[i] += (dm - dp).squaredNorm();
      (*signal)[i] += dm.squaredNorm();
      (*count)[i] += 1;
    }
  }
}

// Replays a recorded base-model field (per frame: the displacement and the contact flags) so that a fit
// which moves only effect parameters runs the effects alone: the base model is the costly part, and its
// output does not depend on effect parameters. Valid only for the base parameters it was recorded with,
// which is why set_params ignores the base part.
class ReplayModel final : public ShearModel {
 public:
  ReplayModel(std::string id, ParamSet params, std::shared_ptr<const std::vector<FieldOutput>> frames)
      : id_(std::move(id)), params_(std::move(params)), frames_(std::move(frames)) {}
  std::string id() const override { return id_; }
  const ParamSet& params() const override { return params_; }
  void set_params(const ParamSet&) override {}
  void reset() override { next_ = 0; }
  void step(const Pose&, double, FieldOutput* out) override {
    if (next_ >= frames_->size()) throw std::logic_error("ReplayModel: stepped past the recorded frames");
    const FieldOutput& f = (*frames_)[next_++];
    out->disp_px = f.disp_px;
    out->marker_in_contact = f.marker_in_contact;
  }
  std::unique_ptr<ShearModel> clone() const override { return std::make_unique<ReplayModel>(*this); }

 private:
  std::string id_;
  ParamSet params_;
  std::shared_ptr<const std::vector<FieldOutput>> frames_;
  std::size_t next_ = 0;
};

using SampleModelFactory = std::function<std::unique_ptr<ShearModel>(const FitSample&, std::size_t)>;

// The base model's field for every frame of every sample, at `params`.
std::vector<std::shared_ptr<const std::vector<FieldOutput>>> record_base(const std::string& model_id,
                                                                         const ParamSet& params,
                                                                         std::shared_ptr<const Sensor> sensor,
                                                                         const std::vector<FitSample>& samples) {
  std::vector<std::shared_ptr<const std::vector<FieldOutput>>> out(samples.size());
  tbb::parallel_for(0, static_cast<int>(samples.size()), [&](int i) {
    auto model = make_model(model_id, sensor, samples[i].indenter);
    ParamSet p = model->params();
    for (std::size_t k = 0; k < p.size(); ++k) {
      const int j = params.index_of(p.specs()[k].name);
      if (j >= 0) p.set(k, params[static_cast<std::size_t>(j)]);
    }
    model->set_params(p);
    model->reset();
    auto frames = std::make_shared<std::vector<FieldOutput>>(samples[i].X_EI.size());
    for (std::size_t k = 0; k < samples[i].X_EI.size(); ++k) {
      FieldOutput& f = (*frames)[k];
      model->step(samples[i].X_EI[k], k == 0 ? 0.0 : samples[i].dt_s, &f);
      f.p_EP.clear();
      f.anchor_EP.clear();
      f.point_state.clear();
    }
    out[i] = std::move(frames);
  });
  return out;
}

// The fingerprints' view of the samples (core/loop/fingerprints.hpp), without the model's field: contact,
// held frames (the held_drift rule), the contact centre in the image and its travel since first contact.
std::vector<FingerprintSample> fingerprint_samples(const Sensor& sensor, const std::vector<FitSample>& samples) {
  std::vector<FingerprintSample> out(samples.size());
  tbb::parallel_for(0, static_cast<int>(samples.size()), [&](int i) {
    const FitSample& s = samples[i];
    FingerprintSample& f = out[i];
    f.dt_s = s.dt_s;
    f.meas_px = s.meas_px;
    bool touched = false;
    Vec2 first_px = Vec2::Zero();
    for (std::size_t k = 0; k < s.X_EI.size(); ++k) {
      const Penetration pen = indenter_penetration(*sensor.gel_sdf, *s.indenter, s.X_EI[k]);
      const Vec2 centre_px = sensor.camera.px_from_E(pen.centre_E);
      if (pen.penetrating && !touched) first_px = centre_px, touched = true;
      const bool still = k > 0 && (s.X_EI[k].translation() - s.X_EI[k - 1].translation()).norm() < kHeldTranslationM &&
                         (s.X_EI[k].linear() - s.X_EI[k - 1].linear()).norm() < kHeldRotation;
      f.in_contact.push_back(pen.penetrating);
      f.held.push_back(pen.penetrating && still);
      f.contact_centre_px.push_back(centre_px);
      f.travel_px.push_back(touched ? (centre_px - first_px).norm() : 0.0);
    }
  });
  return out;
}

Scores score_samples(const SampleModelFactory& make, const ParamSet& params, const std::shared_ptr<const Sensor>& sensor,
                     const std::vector<FitSample>& samples) {
  Scores sc;
  std::vector<double> h_sse(samples.size(), 0.0), h_signal(samples.size(), 0.0), h_count(samples.size(), 0.0);
  sc.sse.assign(samples.size(), 0.0);
  sc.count.assign(samples.size(), 0.0);
  std::vector<MetricsAccumulator> acc(samples.size());
  tbb::parallel_for(0, static_cast<int>(samples.size()), [&](int i) {
    auto model = make(samples[i], static_cast<std::size_t>(i));
    model->set_params(params);
    const auto pred = simulate_sample(*model, samples[i]);
    const std::size_t m = samples[i].meas_px.front().size();
    for (int f : active_marker_frames(samples[i].meas_px)) {
      sc.sse[i] += (pred[f / m][f % m] - samples[i].meas_px[f / m][f % m]).squaredNorm();
      sc.count[i] += 1;
    }
    for (std::size_t k = 0; k < pred.size(); ++k) acc[i].add_frame(pred[k], samples[i].meas_px[k]);
    held_drift(*sensor, samples[i], pred, &sc, static_cast<std::size_t>(i), &h_sse, &h_signal, &h_count);
  });
  for (std::size_t i = 0; i < samples.size(); ++i) {
    sc.metrics.add(samples[i].motion, acc[i]);
    sc.held_sse += h_sse[i];
    sc.held_signal += h_signal[i];
    sc.held_count += h_count[i];
  }
  return sc;
}

ParamSet combined_table(const std::string& model_id, const std::vector<std::string>& effects,
                        const std::shared_ptr<const Sensor>& sensor, const std::vector<FitSample>& samples) {
  return build_model(model_id, effects, sensor, samples.front().indenter)->params();
}

// Copies the values of the names both tables share.
void copy_shared(const ParamSet& from, ParamSet* to) {
  for (std::size_t i = 0; i < to->size(); ++i) {
    const int j = from.index_of(to->specs()[i].name);
    if (j >= 0) to->set(i, from[static_cast<std::size_t>(j)]);
  }
}

// ------------------------------------------------------------------ residual structure

struct Point {          // one scored marker-frame and its covariates
  double err_px;
  double t_contact_s, radial_px, d_centre_mm, d_edge_mm, depth_mm, travel_mm;
  int loading;          // 0 loading, 1 held, 2 unloading, 3 no contact
  // In the contact's own frame (in contact only): the marker's distance outside the contact edge (mm,
  // < 0 inside), the residual along the outward direction and along the travel (px), the side
  // (+1 leading: ahead of the centre along the travel, -1 trailing, 0 no travel yet) and the phase.
  double contact_edge_mm = 0, radial_res_px = 0, along_res_px = 0;
  int side = 0;
  int phase = 4;        // 0 loading, 1 hold, 2 slide, 3 unloading, 4 no contact
};

CovariateTable numeric_table(const std::string& name, const std::string& unit, const std::vector<Point>& pts,
                             double Point::*field, int bins) {
  CovariateTable t;
  t.name = name, t.unit = unit;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& p : pts) {
    lo = std::min(lo, p.*field);
    hi = std::max(hi, p.*field);
  }
  if (pts.empty()) return t;
  if (hi <= lo) hi = lo + 1e-9;
  std::vector<double> sum(bins, 0.0);
  std::vector<long> n(bins, 0);
  for (const auto& p : pts) {
    const int b = std::clamp(static_cast<int>((p.*field - lo) / (hi - lo) * bins), 0, bins - 1);
    sum[b] += p.err_px * p.err_px;
    ++n[b];
  }
  for (int b = 0; b < bins; ++b) {
    const double a = lo + (hi - lo) * b / bins, c = lo + (hi - lo) * (b + 1) / bins;
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.3g-%.3g", a, c);
    t.labels.push_back(buf);
    t.centre.push_back(0.5 * (a + c));
    t.rms_px.push_back(n[b] ? std::sqrt(sum[b] / n[b]) : std::numeric_limits<double>::quiet_NaN());
    t.count.push_back(n[b]);
  }
  return t;
}

CovariateTable loading_table(const std::vector<Point>& pts) {
  CovariateTable t;
  t.name = "loading state";
  t.labels = {"loading", "held", "unloading", "no contact"};
  t.centre = {0, 1, 2, 3};
  std::vector<double> sum(4, 0.0);
  std::vector<long> n(4, 0);
  for (const auto& p : pts) {
    sum[p.loading] += p.err_px * p.err_px;
    ++n[p.loading];
  }
  for (int b = 0; b < 4; ++b) {
    t.rms_px.push_back(n[b] ? std::sqrt(sum[b] / n[b]) : std::numeric_limits<double>::quiet_NaN());
    t.count.push_back(n[b]);
  }
  return t;
}

// A contact-frame table: RMS and mean radial / along-travel residual per bin of the points in contact
// that `bin_of` places (-1: not in this table).
CovariateTable contact_table(const std::string& name, const std::string& unit, std::vector<std::string> labels,
                             const std::vector<Point>& pts, const std::function<int(const Point&)>& bin_of) {
  const int n_bins = static_cast<int>(labels.size());
  CovariateTable t;
  t.name = name, t.unit = unit, t.labels = std::move(labels);
  t.contact_frame = true;
  std::vector<double> sq(n_bins, 0.0), radial(n_bins, 0.0), along(n_bins, 0.0);
  std::vector<long> n(n_bins, 0);
  for (const auto& p : pts) {
    const int b = p.phase == 4 ? -1 : bin_of(p);
    if (b < 0) continue;
    sq[b] += p.err_px * p.err_px, radial[b] += p.radial_res_px, along[b] += p.along_res_px;
    ++n[b];
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int b = 0; b < n_bins; ++b) {
    t.centre.push_back(b);
    t.rms_px.push_back(n[b] ? std::sqrt(sq[b] / n[b]) : nan);
    t.mean_radial_px.push_back(n[b] ? radial[b] / n[b] : nan);
    t.mean_along_px.push_back(n[b] ? along[b] / n[b] : nan);
    t.count.push_back(n[b]);
  }
  return t;
}

// Labels of the bins that fixed edges make: "< e0", "e0 to e1", ..., "> en".
std::vector<std::string> edge_labels(const std::vector<double>& edges) {
  std::vector<std::string> labels = {"< " + format_number(edges.front(), "%g")};
  for (std::size_t b = 0; b + 1 < edges.size(); ++b)
    labels.push_back(format_number(edges[b], "%g") + " to " + format_number(edges[b + 1], "%g"));
  labels.push_back("> " + format_number(edges.back(), "%g"));
  return labels;
}

int edge_bin(const std::vector<double>& edges, double v) {
  return static_cast<int>(std::upper_bound(edges.begin(), edges.end(), v) - edges.begin());
}

// Distance outside the contact edge (mm), on one side of the contact along the travel: fixed bins so
// that reports of different datasets line up.
CovariateTable contact_edge_table(const std::vector<Point>& pts, int side) {
  static const std::vector<double> kEdgesMm = {-4, -2, -1, 0, 1, 2, 4, 8};
  const char* which = side > 0 ? "leading" : side < 0 ? "trailing" : "no travel";
  return contact_table(std::string("contact frame: distance outside the contact edge, ") + which + " side", "mm",
                       edge_labels(kEdgesMm), pts,
                       [side](const Point& p) { return p.side == side ? edge_bin(kEdgesMm, p.contact_edge_mm) : -1; });
}

CovariateTable contact_phase_table(const std::vector<Point>& pts) {
  return contact_table("contact frame: phase", "", {"loading", "hold", "slide", "unloading"}, pts,
                       [](const Point& p) { return p.phase; });
}

// Normal load as penetration depth, in contact only, with the mean radial part (dilation error vs load).
CovariateTable contact_load_table(const std::vector<Point>& pts) {
  static const std::vector<double> kEdgesMm = {0.25, 0.5, 0.75, 1.0, 1.5};
  return contact_table("contact frame: normal load (penetration depth)", "mm", edge_labels(kEdgesMm), pts,
                       [](const Point& p) { return edge_bin(kEdgesMm, p.depth_mm); });
}

// Per-frame contact description of one sample: depth, contact centre and radius, loading state, phase,
// time since first contact and tangential travel since first contact (length and unit direction).
struct FrameContact {
  std::vector<double> depth_m, radius_m, t_contact_s, travel_m;
  std::vector<Vec2> centre_E, travel_dir_E;
  std::vector<int> loading, phase;
};

// Pose changes between frames below these count as "held": no slide.
constexpr double kSlideEpsM = 1e-6;
constexpr double kSlideEpsRad = 1e-5;

bool pose_moved(const Pose& a, const Pose& b) {
  const double dt = (b.translation() - a.translation()).head<2>().norm();
  const double angle = Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle();
  return dt > kSlideEpsM || angle > kSlideEpsRad;
}

FrameContact frame_contacts(const Sensor& sensor, const FitSample& s) {
  FrameContact c;
  const std::size_t F = s.X_EI.size();
  int first = -1;
  for (std::size_t k = 0; k < F; ++k) {
    const Penetration p = indenter_penetration(*sensor.gel_sdf, *s.indenter, s.X_EI[k]);
    c.depth_m.push_back(p.depth_m);
    c.radius_m.push_back(p.radius_m);
    c.centre_E.push_back(p.centre_E);
    if (first < 0 && p.penetrating) first = static_cast<int>(k);
    const double prev = k ? c.depth_m[k - 1] : 0.0;
    c.loading.push_back(!p.penetrating                         ? 3
                        : p.depth_m > prev + kHeldDepthEpsM ? 0
                        : p.depth_m < prev - kHeldDepthEpsM ? 2
                                                             : 1);
    const int load = c.loading.back();
    c.phase.push_back(load == 3 ? 4 : load == 0 ? 0 : load == 2 ? 3 : k && pose_moved(s.X_EI[k - 1], s.X_EI[k]) ? 2 : 1);
  }
  for (std::size_t k = 0; k < F; ++k) {
    const bool after = first >= 0 && static_cast<int>(k) >= first;
    c.t_contact_s.push_back(after ? (k - first) * s.dt_s : 0.0);
    const Vec2 travel = after ? Vec2((s.X_EI[k].translation() - s.X_EI[first].translation()).head<2>()) : Vec2::Zero();
    c.travel_m.push_back(travel.norm());
    c.travel_dir_E.push_back(travel.norm() > kSlideEpsM ? Vec2(travel.normalized()) : Vec2::Zero());
  }
  return c;
}

}  // namespace

std::vector<std::string> model_form_variants(const std::string& model_id) {
  if (model_id == "hydroshear") return {"hydroshear-layer", "hydroshear-stick", "hydroshear-layer-stick", "hydroshear-contact"};
  return {};
}

std::vector<std::string> model_form_hold(const std::string& model_id) {
  if (model_id == "hydroshear") return {"lambda_d", "kappa_d"};
  return {};
}

std::string effect_set_key(const std::vector<std::string>& ids) {
  std::string k;
  for (const auto& id : ids) k += (k.empty() ? "" : "+") + id;
  return k;
}

ResidualStructure analyse_residual(const std::string& model_id, const std::vector<std::string>& effects,
                                   const ParamSet& params, std::shared_ptr<const Sensor> sensor,
                                   const std::vector<FitSample>& samples, int bins) {
  ResidualStructure out;
  const std::size_t M = sensor->markers_rest_px.size();
  std::vector<std::vector<Point>> pts(samples.size());
  std::vector<std::vector<Eigen::VectorXd>> rows(samples.size());
  tbb::parallel_for(0, static_cast<int>(samples.size()), [&](int i) {
    const FitSample& s = samples[i];
    auto model = build_model(model_id, effects, sensor, s.indenter);
    model->set_params(params);
    const auto pred = simulate_sample(*model, s);
    const FrameContact fc = frame_contacts(*sensor, s);
    const auto active = active_marker_frames(s.meas_px);
    int last_frame = -1;
    for (int f : active) {
      const int k = f / static_cast<int>(M), j = f % static_cast<int>(M);
      if (k != last_frame) {
        rows[i].push_back(Eigen::VectorXd::Zero(2 * M));
        last_frame = k;
      }
      const Vec2 e = s.meas_px[k][j] - pred[k][j];
      rows[i].back().segment<2>(2 * j) = e;
      const Vec2 rest = sensor->markers_rest_px[j];
      const Vec2 p = sensor->p_EM[j].head<2>();
      const Vec2 half = 0.5 * sensor->gel.size_m;
      const double edge = std::max(0.0, std::min(half.x() - std::abs(p.x()), half.y() - std::abs(p.y())));
      Point pt{e.norm(), fc.t_contact_s[k], (rest - sensor->camera.principal_px).norm(),
               1e3 * (p - fc.centre_E[k]).norm(), 1e3 * edge, 1e3 * fc.depth_m[k], 1e3 * fc.travel_m[k],
               fc.loading[k]};
      // The image axes are the E axes scaled (Camera::px_from_E), so E directions apply to px residuals.
      const Vec2 out_E = p - fc.centre_E[k];
      const Vec2 dir_E = fc.travel_dir_E[k];
      pt.phase = fc.phase[k];
      pt.contact_edge_mm = 1e3 * (out_E.norm() - fc.radius_m[k]);
      pt.radial_res_px = out_E.norm() > 0 ? e.dot(out_E.normalized()) : 0.0;
      pt.along_res_px = e.dot(dir_E);
      pt.side = dir_E.isZero() ? 0 : out_E.dot(dir_E) >= 0 ? 1 : -1;
      pts[i].push_back(pt);
    }
  });
  std::vector<Point> all;
  std::vector<Eigen::VectorXd> all_rows;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    all.insert(all.end(), pts[i].begin(), pts[i].end());
    all_rows.insert(all_rows.end(), rows[i].begin(), rows[i].end());
  }
  double sse = 0;
  for (const auto& p : all) sse += p.err_px * p.err_px;
  out.marker_frames = static_cast<long>(all.size());
  out.frames = static_cast<long>(all_rows.size());
  out.rmse_px = all.empty() ? std::numeric_limits<double>::quiet_NaN() : std::sqrt(sse / all.size());
  out.covariates.push_back(numeric_table("time since contact", "s", all, &Point::t_contact_s, bins));
  out.covariates.push_back(loading_table(all));
  out.covariates.push_back(numeric_table("radial distance from principal point", "px", all, &Point::radial_px, bins));
  out.covariates.push_back(numeric_table("distance from contact centre", "mm", all, &Point::d_centre_mm, bins));
  out.covariates.push_back(numeric_table("distance from gel edge", "mm", all, &Point::d_edge_mm, bins));
  out.covariates.push_back(numeric_table("penetration depth", "mm", all, &Point::depth_mm, bins));
  out.covariates.push_back(numeric_table("tangential travel", "mm", all, &Point::travel_mm, bins));
  for (int side : {1, -1, 0}) out.covariates.push_back(contact_edge_table(all, side));
  out.covariates.push_back(contact_phase_table(all));
  out.covariates.push_back(contact_load_table(all));

  out.mean_field_px.assign(M, Vec2::Zero());
  out.pc1_px.assign(M, Vec2::Zero());
  if (all_rows.empty()) return out;
  // Principal components: frames x (2 markers), centred by the mean field (reported separately).
  Eigen::MatrixXd R(all_rows.size(), 2 * M);
  for (std::size_t r = 0; r < all_rows.size(); ++r) R.row(r) = all_rows[r].transpose();
  const Eigen::RowVectorXd mean = R.colwise().mean();
  for (std::size_t j = 0; j < M; ++j) out.mean_field_px[j] = Vec2(mean(2 * j), mean(2 * j + 1));
  R.rowwise() -= mean;
  Eigen::BDCSVD<Eigen::MatrixXd> svd(R, Eigen::ComputeThinV);
  const Eigen::VectorXd s2 = svd.singularValues().array().square();
  const double total = s2.sum();
  for (int c = 0; c < 3; ++c) out.explained_variance.push_back(c < s2.size() && total > 0 ? s2(c) / total : 0.0);
  if (svd.singularValues().size() > 0) {
    // Sign convention: the component points along the mean field where it can (else its largest entry > 0).
    Eigen::VectorXd v = svd.matrixV().col(0) * svd.singularValues()(0) / std::sqrt(double(R.rows()));
    const double dot = v.dot(mean.transpose());
    Eigen::Index imax = 0;
    v.cwiseAbs().maxCoeff(&imax);
    if (dot < 0 || (dot == 0 && v(imax) < 0)) v = -v;
    for (std::size_t j = 0; j < M; ++j) out.pc1_px[j] = Vec2(v(2 * j), v(2 * j + 1));
  }
  return out;
}

ResidualReport run_residual_loop(const ResidualInputs& in, const ResidualOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  if (in.calibration.empty()) throw std::invalid_argument("residual: no calibration samples");
  if (in.validation.empty()) throw std::invalid_argument("residual: no validation samples");
  const std::vector<std::string> candidates = o.candidates.empty() ? effect_ids() : o.candidates;
  for (const auto& id : candidates) make_effect(id);   // unknown ids fail before any work

  ResidualReport rep;
  rep.dataset = in.dataset;
  rep.model_id = in.model_id;
  rep.fit_base = o.fit_base;
  rep.sensor = in.sensor;

  FitOptions fo;
  fo.max_iterations = o.max_iterations;
  fo.cancel = o.progress.cancel;
  // A cancelled fit returns its last completed stage; the loop must not score that as a result.
  const auto check_cancel = [&](const CalibrationResult& r) {
    if (r.cancelled || o.progress.cancelled()) throw Cancelled("residual analysis");
  };
  std::vector<std::string> motions = tsd_motions();
  const std::vector<std::string> base_free = o.fit_base ? joint_stage(in.model_id, false).params
                                                        : std::vector<std::string>{};

  // A factory for samples of one split: the full model, or effects over a replayed base field.
  const auto full_model = [&](const std::vector<std::string>& ids) -> SampleModelFactory {
    return [&in, ids](const FitSample& s, std::size_t) { return build_model(in.model_id, ids, in.sensor, s.indenter); };
  };
  const auto finish = [&](const std::vector<std::string>& ids, const ParamSet& params, std::size_t free_params,
                          std::chrono::steady_clock::time_point start, const SampleModelFactory& make_cal,
                          const SampleModelFactory& make_val) {
    EffectFit ef;
    ef.effects = ids;
    ef.fit.params = params;
    ef.fit.free_params = free_params;
    const Scores cal = score_samples(make_cal, params, in.sensor, in.calibration);
    for (std::size_t i = 0; i < cal.sse.size(); ++i) {
      ef.fit.calibration_sse_px2 += cal.sse[i];
      ef.fit.calibration_count += 2 * cal.count[i];
    }
    Scores val = score_samples(make_val, params, in.sensor, in.validation);
    ef.fit.held_sse_px2 = val.held_sse;
    ef.fit.held_signal_px2 = val.held_signal;
    ef.fit.held_count = val.held_count;
    ef.fit.validation.sq_err_px2 = val.sse;
    ef.fit.validation.count = val.count;
    ef.validation = std::move(val.metrics);
    ef.time_s = seconds_since(start);
    return ef;
  };

  // The base model: fitted (joint stage tables of fit.hpp) or as given.
  {
    const auto ts = std::chrono::steady_clock::now();
    ParamSet base = in.base_params;
    if (o.fit_base) {
      FitOptions bo = fo;
      bo.joint = true;
      o.progress("base model fit", 0.0);
      const CalibrationResult br = fit_model(in.model_id, in.sensor, in.calibration, in.base_params, bo);
      check_cancel(br);
      base = br.params;
    }
    rep.fits[""] = finish({}, base, base_free.size(), ts, full_model({}), full_model({}));
  }

  // The model-form round: each variant fitted like the base (its stages, then jointly), starting from the
  // fitted base's values and the variant's own defaults, scored against the base by the selection rule.
  if (o.model_forms && o.fit_base) {
    const FitResult& base_fit = rep.fits.at("").fit;
    // One variant fitted like the base from the fitted base's values (with `hold` held after their first
    // stage), and its score against the base.
    const auto fit_variant = [&](const std::string& v, const std::vector<std::string>& hold) {
      o.progress("model form " + v + (hold.empty() ? "" : ", held after their stage: " + effect_set_key(hold)), 0.0);
      const auto ts = std::chrono::steady_clock::now();
      ParamSet start = default_params(v);
      copy_shared(base_fit.params, &start);
      FitOptions vo = fo;
      vo.joint = true;
      vo.hold = hold;
      const CalibrationResult vr = fit_model(v, in.sensor, in.calibration, start, vo);
      check_cancel(vr);
      const SampleModelFactory make = [&in, v](const FitSample& s, std::size_t) {
        return build_model(v, {}, in.sensor, s.indenter);
      };
      EffectFit ef = finish({}, vr.params, joint_stage(v, false).params.size(), ts, make, make);
      CandidateScore sc = score_candidate(base_fit, ef.fit, o.selection);
      sc.candidate = v;
      return std::pair{std::move(ef), std::move(sc)};
    };
    double best_rmse_px = 0;
    for (const std::string& v : model_form_variants(in.model_id)) {
      auto [ef, sc] = fit_variant(v, {});
      if (sc.accepted && (rep.model_form_selected.empty() || sc.rmse_px < best_rmse_px)) {
        rep.model_form_selected = v;
        best_rmse_px = sc.rmse_px;
      }
      rep.model_form_scores.push_back(std::move(sc));
      rep.model_form_fits[v] = std::move(ef);
    }
    // The selected variant fitted again with the dilation kernel held at the presses' fit: kept when it
    // passes the rule and held-out data prefer it (model_form_hold).
    const std::vector<std::string> hold = model_form_hold(in.model_id);
    if (!rep.model_form_selected.empty() && !hold.empty()) {
      const std::string v = rep.model_form_selected;
      auto [ef, sc] = fit_variant(v, hold);
      if (sc.accepted && sc.rmse_px < best_rmse_px) {
        rep.model_form_held = hold;
        rep.model_form_joint_rmse_px = best_rmse_px;
        for (auto& c : rep.model_form_scores)
          if (c.candidate == v) c = std::move(sc);
        rep.model_form_fits[v] = std::move(ef);
      }
    }
  }

  // The base field of a fitted effect set's base parameters, recorded once per set (calibration and
  // validation samples): effect-only stages and their scores replay it instead of rerunning the base.
  struct Recording {
    std::vector<std::shared_ptr<const std::vector<FieldOutput>>> cal, val;
  };
  std::map<std::string, Recording> recordings;
  const auto recording = [&](const std::string& key) -> const Recording& {
    auto it = recordings.find(key);
    if (it != recordings.end()) return it->second;
    const ParamSet& p = rep.fits.at(key).fit.params;
    Recording r{record_base(in.model_id, p, in.sensor, in.calibration),
                record_base(in.model_id, p, in.sensor, in.validation)};
    return recordings.emplace(key, std::move(r)).first->second;
  };
  const auto replay_model = [&](const std::vector<std::string>& ids, const ParamSet& fitted,
                                const std::vector<std::shared_ptr<const std::vector<FieldOutput>>>& frames)
      -> SampleModelFactory {
    ParamSet base_params = default_params(in.model_id);   // the base's own table (EffectModel splits by it)
    copy_shared(fitted, &base_params);
    const auto* recorded = &frames;   // lives in `recordings` (map nodes are stable)
    return [&in, ids, base_params, recorded](const FitSample& s, std::size_t i) -> std::unique_ptr<ShearModel> {
      auto replay = std::make_unique<ReplayModel>(in.model_id, base_params, recorded->at(i));
      return wrap_with_effects(std::move(replay), ids, in.sensor, s.indenter);
    };
  };

  // The fingerprints (core/loop/fingerprints.hpp): the samples' contact and hold flags once per split, the
  // reference's field once per reference, each candidate's finding once per reference.
  const std::vector<FingerprintSample> fp_cal = fingerprint_samples(*in.sensor, in.calibration);
  const std::vector<FingerprintSample> fp_val = fingerprint_samples(*in.sensor, in.validation);
  std::map<std::string, std::vector<std::string>> held_by_effect;   // parameters a fingerprint settled (full names)
  const auto with_field = [&](std::vector<FingerprintSample> fs, const SampleModelFactory& make, const ParamSet& params,
                              const std::vector<FitSample>& samples) {
    tbb::parallel_for(0, static_cast<int>(samples.size()), [&](int i) {
      auto model = make(samples[i], static_cast<std::size_t>(i));
      model->set_params(params);
      fs[i].pred_px = simulate_sample(*model, samples[i]);
    });
    return fs;
  };
  const auto fingerprint_of = [&](const std::string& id, const std::vector<std::string>& warm) {
    if (!fingerprint_needs_model(id, *in.sensor)) return fingerprint_check(id, *in.sensor, fp_cal, fp_val);
    const std::string warm_key = effect_set_key(warm);
    const Recording& rec = recording(warm_key);
    const ParamSet& p = rep.fits.at(warm_key).fit.params;
    return fingerprint_check(id, *in.sensor, with_field(fp_cal, replay_model(warm, p, rec.cal), p, in.calibration),
                             with_field(fp_val, replay_model(warm, p, rec.val), p, in.validation));
  };

  const FitAndScore fit_and_score = [&](const std::vector<std::string>& ids) -> FitResult {
    const std::string key = effect_set_key(ids);
    if (auto it = rep.fits.find(key); it != rep.fits.end()) return it->second.fit;
    const auto ts = std::chrono::steady_clock::now();
    ParamSet start = combined_table(in.model_id, ids, in.sensor, in.calibration);
    copy_shared(rep.fits.at("").fit.params, &start);
    // Warm start from the fit of the same set without its last effect (the previous greedy round).
    std::vector<std::string> prefix(ids.begin(), ids.end() - (ids.empty() ? 0 : 1));
    std::vector<std::string> warm;
    if (auto it = rep.fits.find(effect_set_key(prefix)); it != rep.fits.end()) {
      copy_shared(it->second.fit.params, &start);
      warm = prefix;
    }
    const std::string warm_key = effect_set_key(warm);
    // The candidate's fingerprint, against the reference (the warm start's model). Found: its parameters are
    // held at the estimate (evidence beyond model form), or fitted as without a fingerprint and checked
    // against its band (evidence model form can mimic: it may add a verdict, never lift one). Not found:
    // fitted alone for the report.
    std::optional<FingerprintCheck> fingerprint;
    const std::string candidate = ids.empty() ? "" : ids.back();
    std::vector<std::string> held_now;   // the candidate's parameters held in this fit (full names)
    const auto full = [&](const std::string& name) { return candidate + kEffectParamSeparator + name; };
    const auto set_clamped = [&](const std::string& name, double value) {
      const ParamSpec& sp = start.specs()[static_cast<std::size_t>(start.index_of(name))];
      start.set(name, std::clamp(value, sp.min, sp.max));
    };
    if (!candidate.empty() && has_fingerprint(candidate) && warm.size() + 1 == ids.size()) {
      o.progress("fingerprint " + candidate, static_cast<double>(rep.fits.size()) /
                                                 static_cast<double>(candidates.size() * o.selection.max_effects + 1));
      fingerprint = fingerprint_of(candidate, warm);
      if (fingerprint->consistent) {
        for (const auto& [name, value] : fingerprint->held) {
          set_clamped(full(name), value);
          held_now.push_back(full(name));
        }
        // Later rounds hold all of them at this fit's values.
        auto& later = held_by_effect[candidate];
        later = held_now;
        for (const auto& b : fingerprint->band) later.push_back(full(b.name));
      }
    }
    const auto held_of = [&](const std::string& id) {
      if (id == candidate) return held_now;
      auto it = held_by_effect.find(id);
      return it == held_by_effect.end() ? std::vector<std::string>{} : it->second;
    };
    // A fingerprint that model form can mimic must agree with the whole-field fit: a fitted value outside its
    // band is a verdict like a bound (the whole field wants something else than the evidence).
    const auto outside_band = [&](const ParamSet& fitted) {
      std::string out;
      if (!fingerprint || !fingerprint->consistent) return out;
      for (const auto& b : fingerprint->band) {
        const double v = fitted.get(full(b.name));
        if (v >= b.low && v <= b.high) continue;
        char buf[200];
        std::snprintf(buf, sizeof buf, "%s%s = %.4g outside its fingerprint's band [%.4g, %.4g]", out.empty() ? "" : ", ",
                      full(b.name).c_str(), v, b.low, b.high);
        out += buf;
      }
      return out;
    };
    std::vector<FitStage> stages;
    std::vector<std::string> joint = base_free;
    for (const auto& id : ids) {
      const auto free = effect_free_params(start, id, held_of(id));
      joint.insert(joint.end(), free.begin(), free.end());
      if (std::find(warm.begin(), warm.end(), id) == warm.end() && !free.empty())
        stages.push_back({"effect:" + id, free, motions, false, {}});
    }
    o.progress("fit " + in.model_id + "+" + key, static_cast<double>(rep.fits.size()) /
                                                     static_cast<double>(candidates.size() * o.selection.max_effects + 1));
    // (1) The new effects alone, over the recorded field of the warm start's base (cheap: no base runs).
    const Recording& rec = recording(warm_key);
    const ParamSet& base_params = rep.fits.at(warm_key).fit.params;
    const auto replay_cal = replay_model(ids, base_params, rec.cal);
    const auto replay_val = replay_model(ids, base_params, rec.val);
    CalibrationResult er{in.model_id + "+" + key, start, {}, false, 0};
    if (!stages.empty()) er = run_fit_stages_per_sample(in.model_id + "+" + key, replay_cal, stages, in.calibration, start, fo);
    check_cancel(er);
    std::size_t free_count = 0;
    for (const auto& st : stages) free_count += st.params.size();
    EffectFit ef = finish(ids, er.params, free_count + rep.fits.at(warm_key).fit.free_params, ts, replay_cal, replay_val);
    // (2) Screen: the joint refit (every run reruns the base model) only for an effect that alone, over
    // the reference's base, already buys part of the acceptance margin on validation, or whose fingerprint
    // was found. Joint refits may let the base parameters lean on the effect, but an effect the data hold
    // shows on the base as fitted.
    const double ref_rmse = validation_rmse(rep.fits.at(warm_key).fit.validation);
    const double alone_pct = 100.0 * (ref_rmse - validation_rmse(ef.fit.validation)) / ref_rmse;
    const double fp = fingerprint_explained_pct(rep.fits.at(warm_key).fit, ef.fit, o.selection);
    const bool drift = std::isfinite(fp) && fp >= o.selection.min_fingerprint_pct;
    const bool promising = fingerprint ? fingerprint->consistent : (alone_pct >= o.screen_min_pct || drift);
    const std::size_t joint_count = joint.size();
    if (!promising || joint_count == free_count) {
      if (joint_count > free_count && !fingerprint) {
        char why[160];
        std::snprintf(why, sizeof why, "screened: alone over the fitted base it gains %.2f%% (< %.2f%%), no joint refit",
                      alone_pct, o.screen_min_pct);
        ef.fit.veto = why;
      }
    } else {
      const std::vector<FitStage> joint_stage_only{{"joint", joint, motions, false, {}}};
      const CalibrationResult cr =
          run_fit_stages(in.model_id + "+" + key, [&](std::shared_ptr<const Indenter> ind) {
            return build_model(in.model_id, ids, in.sensor, ind);
          }, joint_stage_only, in.calibration, er.params, fo);
      check_cancel(cr);
      ef = finish(ids, cr.params, joint_count, ts, full_model(ids), full_model(ids));
    }
    if (ef.fit.veto.empty() && !candidate.empty()) {
      const std::string bound = params_at_bound(ef.fit.params, candidate, held_of(candidate));
      const std::string band = outside_band(ef.fit.params);
      if (!bound.empty()) {
        ef.fit.veto = "model-form symptom: " + bound + " at a bound of its physical range";
        ef.fit.model_form_symptom = true;
      } else if (!band.empty()) {
        ef.fit.veto = "model-form symptom: " + band + ": the whole field disagrees with the evidence";
        ef.fit.model_form_symptom = true;
      }
    }
    ef.fit.fingerprint = fingerprint;
    ef.time_s = seconds_since(ts);
    rep.fits[key] = ef;
    return rep.fits[key].fit;
  };

  rep.selection = select_effects(candidates, fit_and_score, o.selection);
  o.progress("residual structure", 1.0);
  rep.before = rep.fits.at("");
  rep.after = rep.fits.at(effect_set_key(rep.selection.selected));
  std::vector<FitSample> everything = in.calibration;
  everything.insert(everything.end(), in.validation.begin(), in.validation.end());
  rep.structure_before = analyse_residual(in.model_id, {}, rep.before.fit.params, in.sensor, everything, o.bins);
  rep.structure_after = analyse_residual(in.model_id, rep.selection.selected, rep.after.fit.params, in.sensor,
                                         everything, o.bins);
  rep.time_s = seconds_since(t0);
  return rep;
}

nlohmann::ordered_json effect_params_json(const ParamSet& params, const std::string& effect_id) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  const std::string prefix = effect_id + kEffectParamSeparator;
  for (std::size_t i = 0; i < params.size(); ++i) {
    const std::string& n = params.specs()[i].name;
    if (n.rfind(prefix, 0) == 0) j[n.substr(prefix.size())] = params[i];
  }
  return j;
}

}  // namespace sb
